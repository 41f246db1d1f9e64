// The glTF subset our scenes use: node hierarchies (TRS and matrix), interleaved buffers
// (byteStride), uint16 indices, data URIs, .glb, missing normals and materials, textures.
#include <gtest/gtest.h>

#include <fstream>

#include "splat/raytrace/gltf_mesh.hpp"
#include "tests/raytrace/scene_test_files.hpp"
#include "splat/raytrace/shading.hpp"
#include "splat/data/image_io.hpp"
#include "tests/test_support.hpp"

namespace splat::raytrace {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string base64(const std::string& bytes) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    unsigned v = unsigned(static_cast<unsigned char>(bytes[i])) << 16;
    if (i + 1 < bytes.size()) v |= unsigned(static_cast<unsigned char>(bytes[i + 1])) << 8;
    if (i + 2 < bytes.size()) v |= static_cast<unsigned char>(bytes[i + 2]);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(v >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kAlphabet[v & 63] : '=';
  }
  return out;
}

template <class T>
void append(std::string& bytes, std::initializer_list<T> values) {
  for (T v : values) bytes.append(reinterpret_cast<const char*>(&v), sizeof(T));
}

// One triangle (0,0,0), (1,0,0), (0,1,0) with +z normals, interleaved position+normal
// (stride 24) and uint16 indices, drawn by a child node (rotation 90° about y, scale 2) of a
// translated parent; and the same triangle without normals or material through a matrix node.
// Returns the document and its binary buffer.
std::pair<json, std::string> hierarchy_gltf() {
  std::string bin;
  append<float>(bin, {0, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 1});  // 72 bytes
  append<std::uint16_t>(bin, {0, 1, 2, 0});                                    // 8 bytes, padded
  const float s = std::sqrt(0.5f);
  json doc = {
      {"asset", {{"version", "2.0"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0, 2}}}}},
      {"nodes", {{{"translation", {1, 2, 3}}, {"children", {1}}},
                 {{"mesh", 0}, {"rotation", {0, s, 0, s}}, {"scale", {2, 2, 2}}},
                 {{"mesh", 1}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 5, 0, 0, 1}}}}},
      {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}, {"indices", 2},
                                    {"material", 0}, {"mode", 4}}}}},
                  {{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 2}}}}}}},
      {"materials", {{{"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.25, 1, 1}},
                                                {"metallicFactor", 0.2}, {"roughnessFactor", 0.7}}}}}},
      {"bufferViews", {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 72}, {"byteStride", 24}},
                       {{"buffer", 0}, {"byteOffset", 72}, {"byteLength", 6}}}},
      {"accessors", {{{"bufferView", 0}, {"byteOffset", 0}, {"componentType", 5126}, {"count", 3},
                      {"type", "VEC3"}, {"min", {0, 0, 0}}, {"max", {1, 1, 0}}},
                     {{"bufferView", 0}, {"byteOffset", 12}, {"componentType", 5126}, {"count", 3},
                      {"type", "VEC3"}},
                     {{"bufferView", 1}, {"componentType", 5123}, {"count", 3}, {"type", "SCALAR"}}}},
      {"buffers", {{{"byteLength", bin.size()}}}}};
  return {doc, bin};
}

void expect_vec3(const glm::vec3& a, const glm::vec3& b) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-5f) << c;
}

void expect_hierarchy_mesh(const Mesh& mesh) {
  ASSERT_EQ(mesh.triangle_count(), 2u);
  // Child: scale 2, then 90° about y (x → −z, z → x), then the parent's translation.
  const std::uint32_t* t0 = &mesh.indices[0];
  expect_vec3(mesh.positions[t0[0]], {1, 2, 3});
  expect_vec3(mesh.positions[t0[1]], {1, 2, 1});
  expect_vec3(mesh.positions[t0[2]], {1, 4, 3});
  expect_vec3(mesh.normals[t0[0]], {1, 0, 0});
  const Material& m0 = mesh.materials[mesh.triangle_material[0]];
  EXPECT_FLOAT_EQ(m0.base_color.g, 0.25f);
  EXPECT_FLOAT_EQ(m0.metallic, 0.2f);
  EXPECT_FLOAT_EQ(m0.roughness, 0.7f);
  // Matrix node: translation by (5, 0, 0); no NORMAL → face normal; no material → default.
  const std::uint32_t* t1 = &mesh.indices[3];
  expect_vec3(mesh.positions[t1[1]], {6, 0, 0});
  expect_vec3(mesh.normals[t1[0]], {0, 0, 1});
  const Material& m1 = mesh.materials[mesh.triangle_material[1]];
  EXPECT_EQ(m1.base_color, glm::vec4(1.0f));
  EXPECT_EQ(m1.metallic, 1.0f);
  EXPECT_EQ(m1.roughness, 1.0f);
  EXPECT_EQ(m1.texture, -1);
}

TEST(SceneGltf, NodeTransformsStridesAndDataUris) {
  const fs::path dir = test::scratch_dir("scene_gltf_hierarchy");
  auto [doc, bin] = hierarchy_gltf();
  doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(bin);
  test::write_json(dir / "h.gltf", doc);
  expect_hierarchy_mesh(load_gltf_mesh(dir / "h.gltf"));
}

TEST(SceneGltf, BinaryGlbLoadsTheSame) {
  const fs::path dir = test::scratch_dir("scene_gltf_glb");
  auto [doc, bin] = hierarchy_gltf();
  std::string text = doc.dump();
  while (text.size() % 4) text += ' ';
  while (bin.size() % 4) bin += '\0';
  std::string glb;
  append<std::uint32_t>(glb, {0x46546C67u, 2u, std::uint32_t(12 + 8 + text.size() + 8 + bin.size())});
  append<std::uint32_t>(glb, {std::uint32_t(text.size()), 0x4E4F534Au});  // "JSON"
  glb += text;
  append<std::uint32_t>(glb, {std::uint32_t(bin.size()), 0x004E4942u});  // "BIN\0"
  glb += bin;
  std::ofstream(dir / "h.glb", std::ios::binary) << glb;
  expect_hierarchy_mesh(load_gltf_mesh(dir / "h.glb"));
}

TEST(SceneGltf, TexturesAreDecodedFromSrgbAndWrap) {
  const fs::path dir = test::scratch_dir("scene_gltf_texture");
  Image texels(2, 1, 3);
  for (int c = 0; c < 3; ++c) {
    texels.at(0, 0, c) = 128.0f / 255.0f;
    texels.at(1, 0, c) = 1.0f;
  }
  write_png(texels, dir / "tex.png", 8);
  test::write_test_gltf(dir / "t.gltf", test::plane_mesh(1, 0), "tex.png");
  const Mesh mesh = load_gltf_mesh(dir / "t.gltf");
  ASSERT_EQ(mesh.textures.size(), 1u);
  ASSERT_EQ(mesh.materials[mesh.triangle_material[0]].texture, 0);
  const Texture& tex = mesh.textures[0];
  const float dark = std::pow((128.0f / 255.0f + 0.055f) / 1.055f, 2.4f);  // ≈ 0.216
  EXPECT_NEAR(sample_texture(tex, {0.25f, 0.5f}).r, dark, 1e-5f);  // texel 0's centre
  EXPECT_NEAR(sample_texture(tex, {0.75f, 0.5f}).g, 1.0f, 1e-5f);  // texel 1's centre
  EXPECT_NEAR(sample_texture(tex, {1.25f, 0.5f}).b, dark, 1e-5f);  // wrapped around
  EXPECT_NEAR(sample_texture(tex, {0.5f, 0.5f}).r, 0.5f * (dark + 1.0f), 1e-5f);  // bilinear
  EXPECT_NEAR(sample_texture(tex, {0.0f, 0.5f}).r, 0.5f * (dark + 1.0f), 1e-5f);  // across the seam
  EXPECT_FLOAT_EQ(sample_texture(tex, {0.25f, 0.5f}).a, 1.0f);
}

}  // namespace
}  // namespace splat::raytrace
