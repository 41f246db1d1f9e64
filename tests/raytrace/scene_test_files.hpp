#pragma once
// Tiny glTF files and scene specs written by the scene tests into their scratch folders.
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace splat::test {

struct TestMesh {
  std::vector<float> positions;        // [V, 3]
  std::vector<float> normals;          // [V, 3] or empty (face normals)
  std::vector<std::uint32_t> indices;  // [T, 3]
};

// A square of half-size `half` in the plane y = `height`, facing +y.
inline TestMesh plane_mesh(float half, float height) {
  return {{-half, height, -half, half, height, -half, half, height, half, -half, height, half},
          {0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0},
          {0, 2, 1, 0, 3, 2}};
}

// The axis-aligned cube [-h, h]^3, flat faces (no normals: the loader makes face normals).
inline TestMesh cube_mesh(float h) {
  TestMesh m;
  for (int i = 0; i < 8; ++i)
    for (int axis = 0; axis < 3; ++axis) m.positions.push_back((i >> axis) & 1 ? h : -h);
  // Two triangles per face; winding does not matter to the renderer.
  m.indices = {0, 1, 3, 0, 3, 2, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
               2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 3, 7, 1, 7, 5};
  return m;
}

// A UV sphere of `radius` at the origin with smooth normals.
inline TestMesh sphere_mesh(float radius, int rings, int segments) {
  TestMesh m;
  for (int r = 0; r <= rings; ++r) {
    const double theta = std::numbers::pi * r / rings;
    for (int s = 0; s <= segments; ++s) {
      const double phi = 2 * std::numbers::pi * s / segments;
      const float n[3] = {float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)),
                          float(std::sin(theta) * std::sin(phi))};
      for (int c = 0; c < 3; ++c) {
        m.positions.push_back(radius * n[c]);
        m.normals.push_back(n[c]);
      }
    }
  }
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const std::uint32_t a = r * (segments + 1) + s, b = a + segments + 1;
      m.indices.insert(m.indices.end(), {a, b, a + 1, a + 1, b, b + 1});
    }
  return m;
}

// Writes `gltf` and its buffer `<stem>.bin` beside it. With `texture_uri`, the material
// takes its base colour from that image (and every vertex gets UV (0.5, 0.5)).
inline void write_test_gltf(const std::filesystem::path& gltf, const TestMesh& mesh,
                            const std::string& texture_uri = "") {
  using nlohmann::json;
  const std::size_t vertex_count = mesh.positions.size() / 3;
  std::vector<float> uvs(texture_uri.empty() ? 0 : 2 * vertex_count, 0.5f);
  std::string bytes;
  auto append = [&](const void* data, std::size_t size) {
    const std::size_t offset = bytes.size();
    bytes.append(static_cast<const char*>(data), size);
    return offset;
  };
  json views = json::array(), accessors = json::array(), attributes;
  auto add = [&](const void* data, std::size_t size, int component, const char* type,
                 std::size_t count) {
    views.push_back({{"buffer", 0}, {"byteOffset", append(data, size)}, {"byteLength", size}});
    accessors.push_back({{"bufferView", views.size() - 1}, {"componentType", component},
                         {"count", count}, {"type", type}});
    return int(accessors.size() - 1);
  };
  float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
  for (std::size_t v = 0; v < vertex_count; ++v)
    for (int c = 0; c < 3; ++c) {
      lo[c] = std::min(lo[c], mesh.positions[3 * v + c]);
      hi[c] = std::max(hi[c], mesh.positions[3 * v + c]);
    }
  attributes["POSITION"] = add(mesh.positions.data(), mesh.positions.size() * 4, 5126, "VEC3", vertex_count);
  accessors.back()["min"] = {lo[0], lo[1], lo[2]};
  accessors.back()["max"] = {hi[0], hi[1], hi[2]};
  if (!mesh.normals.empty())
    attributes["NORMAL"] = add(mesh.normals.data(), mesh.normals.size() * 4, 5126, "VEC3", vertex_count);
  if (!uvs.empty()) attributes["TEXCOORD_0"] = add(uvs.data(), uvs.size() * 4, 5126, "VEC2", vertex_count);
  const int indices = add(mesh.indices.data(), mesh.indices.size() * 4, 5125, "SCALAR", mesh.indices.size());
  json material = {{"pbrMetallicRoughness",
                    {{"baseColorFactor", {0.8, 0.6, 0.4, 1.0}}, {"metallicFactor", 0.0},
                     {"roughnessFactor", 0.5}}}};
  json doc = {{"asset", {{"version", "2.0"}}},
              {"scene", 0},
              {"scenes", json::array({{{"nodes", {0}}}})},
              {"nodes", json::array({{{"mesh", 0}}})},
              {"meshes", json::array({{{"primitives", json::array({{{"attributes", attributes},
                                                                    {"indices", indices},
                                                                    {"material", 0}}})}}})},
              {"bufferViews", views},
              {"accessors", accessors}};
  if (!texture_uri.empty()) {
    material["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    doc["textures"] = json::array({{{"source", 0}}});
    doc["images"] = json::array({{{"uri", texture_uri}}});
  }
  // json::array() spelled out: a braced list of one json value is an array for GCC but a
  // copy of the value for clang.
  doc["materials"] = json::array({material});
  const std::string bin_name = gltf.stem().string() + ".bin";
  doc["buffers"] = json::array({{{"uri", bin_name}, {"byteLength", bytes.size()}}});
  std::ofstream(gltf.parent_path() / bin_name, std::ios::binary) << bytes;
  std::ofstream(gltf) << doc.dump(1);
}

// A scene spec as JSON (tests edit it before writing): tiny and fast to render.
inline nlohmann::json tiny_spec(const std::string& gltf) {
  return {{"description", "test scene"},
          {"gltf", gltf},
          {"cameras", {{"rig", "orbit"}, {"target", {0, 0, 0}}, {"radius", 4.0},
                       {"elevation_deg", {10, 60}}, {"fov_deg", 40}, {"width", 24},
                       {"height", 16}, {"train", 3}, {"test", 2}}},
          {"lights", {{{"type", "directional"}, {"direction", {-0.3, -1, -0.5}},
                       {"color", {1, 1, 1}}, {"intensity", 2.0}},
                      {{"type", "point"}, {"position", {2, 3, 2}}, {"color", {1, 1, 1}},
                       {"intensity", 20.0}}}},
          {"ambient", {0.25, 0.25, 0.25}},
          {"background", nullptr},
          {"samples_per_pixel", 4},
          {"seed", 0}};
}

inline void write_json(const std::filesystem::path& file, const nlohmann::json& doc) {
  std::ofstream(file) << doc.dump(1);
}

}  // namespace splat::test
