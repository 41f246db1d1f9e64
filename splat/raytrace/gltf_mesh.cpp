#include "splat/raytrace/gltf_mesh.hpp"

#include <cmath>
#include <fstream>
#include <cstring>
#include <string>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "splat/core/error.hpp"
#include "splat/core/json_file.hpp"

namespace splat::raytrace {
namespace {

namespace fs = std::filesystem;

// No coordinate, scale or transform entry of a glTF may exceed this in magnitude
// (docs/DESIGN.md §4.8): beyond it the ray tracer's floats lose all precision.
constexpr double kMaxGltfMagnitude = 1e6;

bool usable_number(double v) { return std::abs(v) <= kMaxGltfMagnitude; }  // also false for NaN

// The byte offset of an accessor's first element, after checking that `count` elements of
// `element` bytes, `stride` apart, lie inside its buffer view and the view inside its buffer.
// Every sum is checked before it is formed: offsets come from the file and may be anything.
std::size_t checked_accessor_start(const fs::path& file, const tinygltf::Model& model,
                                   const tinygltf::Accessor& acc, std::size_t element, const std::string& what) {
  const tinygltf::BufferView& view = model.bufferViews[std::size_t(acc.bufferView)];
  if (view.buffer < 0 || view.buffer >= int(model.buffers.size()))
    throw InputError(file, what + ": bufferView without a valid buffer");
  const std::size_t buffer_size = model.buffers[std::size_t(view.buffer)].data.size();
  const int stride = acc.ByteStride(view);
  const bool view_fits = view.byteOffset <= buffer_size && view.byteLength <= buffer_size - view.byteOffset;
  const std::size_t view_size = view_fits ? view.byteLength : 0;
  const bool fits = view_fits && stride > 0 && acc.byteOffset <= view_size &&
                    (acc.count == 0 ||
                     (acc.count - 1 <= (view_size - acc.byteOffset) / std::size_t(stride) &&
                      (acc.count - 1) * std::size_t(stride) + element <= view_size - acc.byteOffset));
  if (!fits) throw InputError(file, what + ": accessor reaches outside its buffer view or buffer");
  return view.byteOffset + acc.byteOffset;
}

float srgb_to_linear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

// Reads accessor `index` as `components` floats per element, honouring byteStride.
std::vector<float> read_floats(const fs::path& file, const tinygltf::Model& model, int index,
                               int type, int components, const char* what) {
  if (index < 0 || index >= int(model.accessors.size()))
    throw InputError(file, std::string(what) + ": accessor index out of range");
  const tinygltf::Accessor& acc = model.accessors[index];
  if (acc.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || acc.type != type)
    throw InputError(file, std::string(what) + ": accessor " + std::to_string(index) +
                               " must hold float vectors of " + std::to_string(components));
  if (acc.bufferView < 0 || acc.bufferView >= int(model.bufferViews.size()))
    throw InputError(file, std::string(what) + ": accessor without a valid bufferView");
  const tinygltf::BufferView& view = model.bufferViews[acc.bufferView];
  const std::size_t element = sizeof(float) * components;
  const std::size_t start = checked_accessor_start(file, model, acc, element, std::string(what));
  const tinygltf::Buffer& buffer = model.buffers[std::size_t(view.buffer)];
  const std::size_t stride = std::size_t(acc.ByteStride(view));
  std::vector<float> out(acc.count * components);
  for (std::size_t i = 0; i < acc.count; ++i)
    std::memcpy(&out[i * components], buffer.data.data() + start + i * stride, element);
  for (std::size_t i = 0; i < out.size(); ++i)
    if (!usable_number(out[i]))
      throw InputError(file, std::string(what) + ": element " + std::to_string(i / components) +
                                 " is not finite or exceeds 1e6 in magnitude");
  return out;
}

std::vector<std::uint32_t> read_indices(const fs::path& file, const tinygltf::Model& model,
                                        int index) {
  if (index < 0 || index >= int(model.accessors.size()))
    throw InputError(file, "indices: accessor index out of range");
  const tinygltf::Accessor& acc = model.accessors[index];
  int size = 0;
  if (acc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) size = 2;
  else if (acc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) size = 4;
  else if (acc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) size = 1;
  if (size == 0 || acc.type != TINYGLTF_TYPE_SCALAR || acc.bufferView < 0 ||
      acc.bufferView >= int(model.bufferViews.size()))
    throw InputError(file, "indices: accessor " + std::to_string(index) +
                               " must hold unsigned scalars in a bufferView");
  const tinygltf::BufferView& view = model.bufferViews[acc.bufferView];
  const std::size_t start = checked_accessor_start(file, model, acc, std::size_t(size), "indices");
  const tinygltf::Buffer& buffer = model.buffers[std::size_t(view.buffer)];
  const std::size_t stride = std::size_t(acc.ByteStride(view));
  std::vector<std::uint32_t> out(acc.count);
  for (std::size_t i = 0; i < acc.count; ++i) {
    const unsigned char* p = buffer.data.data() + start + i * stride;
    if (size == 1) out[i] = p[0];
    else if (size == 2) { std::uint16_t v; std::memcpy(&v, p, 2); out[i] = v; }
    else std::memcpy(&out[i], p, 4);
  }
  return out;
}

// The node's transform; InputError for a malformed one (a matrix that is not 16 numbers, a
// rotation that is not a non-zero quaternion, a value that is not finite or too large).
glm::mat4 local_transform(const fs::path& file, const tinygltf::Node& node, int index) {
  const std::string where = "node " + std::to_string(index) + ": ";
  const auto check = [&](const std::vector<double>& values, std::size_t size, const char* name) {
    if (!values.empty() && values.size() != size)
      throw InputError(file, where + "\"" + name + "\" must hold " + std::to_string(size) + " numbers");
    for (double v : values)
      if (!usable_number(v)) throw InputError(file, where + "\"" + name + "\" has a value that is not finite or exceeds 1e6");
  };
  check(node.matrix, 16, "matrix");
  check(node.translation, 3, "translation");
  check(node.rotation, 4, "rotation");
  check(node.scale, 3, "scale");
  if (node.rotation.size() == 4 &&
      !(std::abs(node.rotation[0]) + std::abs(node.rotation[1]) + std::abs(node.rotation[2]) +
            std::abs(node.rotation[3]) > 1e-12))
    throw InputError(file, where + "\"rotation\" is a zero quaternion");
  if (node.matrix.size() == 16) {
    glm::dmat4 m;  // glTF matrices are column-major, as glm's
    for (int i = 0; i < 16; ++i) glm::value_ptr(m)[i] = node.matrix[i];
    return glm::mat4(m);
  }
  glm::dmat4 t(1.0), r(1.0), s(1.0);
  if (node.translation.size() == 3)
    t[3] = glm::dvec4(node.translation[0], node.translation[1], node.translation[2], 1.0);
  if (node.rotation.size() == 4)  // glTF stores (x, y, z, w); glm's constructor takes w first
    r = glm::mat4_cast(glm::normalize(
        glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2])));
  if (node.scale.size() == 3)
    s = glm::scale(glm::dmat4(1.0), glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
  return glm::mat4(t * r * s);
}

class Flattener {
 public:
  Flattener(const fs::path& file, const tinygltf::Model& model, Mesh& mesh)
      : file_(file), model_(model), mesh_(mesh) {}

  void node(int index, const glm::mat4& parent, int depth) {
    if (index < 0 || index >= int(model_.nodes.size()))
      throw InputError(file_, "node index " + std::to_string(index) + " out of range");
    if (depth > 64) throw InputError(file_, "node hierarchy deeper than 64 (a cycle?)");
    const tinygltf::Node& n = model_.nodes[index];
    const glm::mat4 world = parent * local_transform(file_, n, index);
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (!usable_number(world[c][r]))
          throw InputError(file_, "node " + std::to_string(index) + ": its world transform exceeds 1e6");
    if (n.mesh >= 0) {
      if (n.mesh >= int(model_.meshes.size()))
        throw InputError(file_, "node " + std::to_string(index) + ": mesh index out of range");
      for (const tinygltf::Primitive& p : model_.meshes[n.mesh].primitives) primitive(p, world);
    }
    for (int child : n.children) node(child, world, depth + 1);
  }

 private:
  void primitive(const tinygltf::Primitive& prim, const glm::mat4& world) {
    if (prim.mode != -1 && prim.mode != TINYGLTF_MODE_TRIANGLES)
      throw InputError(file_, "only triangle primitives (mode 4) are supported, got mode " +
                                  std::to_string(prim.mode));
    const auto position_it = prim.attributes.find("POSITION");
    if (position_it == prim.attributes.end())
      throw InputError(file_, "a primitive has no POSITION attribute");
    const std::vector<float> pos =
        read_floats(file_, model_, position_it->second, TINYGLTF_TYPE_VEC3, 3, "POSITION");
    const std::size_t vertex_count = pos.size() / 3;
    std::vector<float> nrm, uv;
    if (auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end())
      nrm = read_floats(file_, model_, it->second, TINYGLTF_TYPE_VEC3, 3, "NORMAL");
    if (auto it = prim.attributes.find("TEXCOORD_0"); it != prim.attributes.end())
      uv = read_floats(file_, model_, it->second, TINYGLTF_TYPE_VEC2, 2, "TEXCOORD_0");
    if ((!nrm.empty() && nrm.size() != pos.size()) || (!uv.empty() && uv.size() / 2 != vertex_count))
      throw InputError(file_, "a primitive's attributes have different counts");
    std::vector<std::uint32_t> idx;
    if (prim.indices >= 0) {
      idx = read_indices(file_, model_, prim.indices);
    } else {
      idx.resize(vertex_count);
      for (std::size_t i = 0; i < vertex_count; ++i) idx[i] = std::uint32_t(i);
    }
    if (idx.size() % 3 != 0) throw InputError(file_, "a triangle primitive's index count is not a multiple of 3");
    for (std::uint32_t i : idx)
      if (i >= vertex_count) throw InputError(file_, "a vertex index is out of range");
    if (prim.material >= int(model_.materials.size()))
      throw InputError(file_, "a primitive's material index is out of range");
    const int material = prim.material >= 0 ? prim.material : int(mesh_.materials.size()) - 1;

    // Normals transform by the inverse transpose, so non-uniform scales keep them perpendicular.
    const glm::mat3 normal_matrix = glm::transpose(glm::inverse(glm::mat3(world)));
    auto world_pos = [&](std::uint32_t v) {
      return glm::vec3(world * glm::vec4(pos[3 * v], pos[3 * v + 1], pos[3 * v + 2], 1.0f));
    };
    auto uv_of = [&](std::uint32_t v) {
      return uv.empty() ? glm::vec2(0.0f) : glm::vec2(uv[2 * v], uv[2 * v + 1]);
    };
    if (!nrm.empty()) {
      const std::uint32_t base = std::uint32_t(mesh_.positions.size());
      for (std::uint32_t v = 0; v < vertex_count; ++v) {
        mesh_.positions.push_back(world_pos(v));
        const glm::vec3 n = normal_matrix * glm::vec3(nrm[3 * v], nrm[3 * v + 1], nrm[3 * v + 2]);
        const float len = glm::length(n);
        mesh_.normals.push_back(len > 0 ? n / len : glm::vec3(0, 1, 0));
        mesh_.uvs.push_back(uv_of(v));
      }
      for (std::uint32_t i : idx) mesh_.indices.push_back(base + i);
    } else {
      // No NORMAL: flat shading, so every triangle gets its own three vertices.
      for (std::size_t t = 0; t < idx.size(); t += 3) {
        const glm::vec3 a = world_pos(idx[t]), b = world_pos(idx[t + 1]), c = world_pos(idx[t + 2]);
        const glm::vec3 n = glm::cross(b - a, c - a);
        const float len = glm::length(n);
        const glm::vec3 face = len > 0 ? n / len : glm::vec3(0, 1, 0);
        for (int k = 0; k < 3; ++k) {
          mesh_.indices.push_back(std::uint32_t(mesh_.positions.size()));
          mesh_.positions.push_back(k == 0 ? a : k == 1 ? b : c);
          mesh_.normals.push_back(face);
          mesh_.uvs.push_back(uv_of(idx[t + k]));
        }
      }
    }
    mesh_.triangle_material.insert(mesh_.triangle_material.end(), idx.size() / 3, material);
  }

  const fs::path& file_;
  const tinygltf::Model& model_;
  Mesh& mesh_;
};

Texture decode_texture(const fs::path& file, const tinygltf::Model& model, int texture_index) {
  const tinygltf::Texture& tex = model.textures[texture_index];
  if (tex.source < 0 || tex.source >= int(model.images.size()))
    throw InputError(file, "texture " + std::to_string(texture_index) + " has no image");
  const tinygltf::Image& img = model.images[tex.source];
  const int channels = img.component;
  const int bytes = img.bits / 8;
  if (img.width <= 0 || img.height <= 0 || channels < 1 || channels > 4 || (bytes != 1 && bytes != 2) ||
      img.image.size() != std::size_t(img.width) * img.height * channels * bytes)
    throw InputError(file, "image " + std::to_string(tex.source) + " (" + img.uri +
                               ") did not decode to 8- or 16-bit pixels");
  Texture out;
  out.width = img.width;
  out.height = img.height;
  out.texels.resize(std::size_t(img.width) * img.height);
  const float scale = bytes == 1 ? 1.0f / 255.0f : 1.0f / 65535.0f;
  for (std::size_t p = 0; p < out.texels.size(); ++p) {
    float v[4] = {0, 0, 0, 1};
    for (int c = 0; c < channels; ++c) {
      const unsigned char* s = &img.image[(p * channels + c) * bytes];
      v[c] = float(bytes == 1 ? s[0] : (unsigned(s[0]) | unsigned(s[1]) << 8)) * scale;
    }
    if (channels <= 2) {  // grey (+ alpha): spread the grey, move alpha to the end
      v[3] = channels == 2 ? v[1] : 1.0f;
      v[1] = v[2] = v[0];
    }
    // Base colour textures are sRGB-encoded (glTF spec); alpha is linear.
    out.texels[p] = glm::vec4(srgb_to_linear(v[0]), srgb_to_linear(v[1]), srgb_to_linear(v[2]), v[3]);
  }
  return out;
}

// tinygltf's own (stb) image decoder, wrapped so that a failure names the image's file:
// tinygltf's message gives only the image's index and name, which is often empty.
bool load_image_naming_uri(tinygltf::Image* image, int index, std::string* err, std::string* warn,
                           int width, int height, const unsigned char* bytes, int size, void* user) {
  if (tinygltf::LoadImageData(image, index, err, warn, width, height, bytes, size, user)) return true;
  if (err) {
    while (!err->empty() && (err->back() == '\n' || err->back() == ' ')) err->pop_back();
    const bool embedded = image->uri.rfind("data:", 0) == 0 || image->uri.empty();
    *err += embedded ? " (an embedded image)" : " (image \"" + image->uri + "\")";
    *err += "\n";
  }
  return false;
}

// tinygltf takes a negative offset, length or count for "absent" and goes on with its default
// (0), so a damaged file would load as a different mesh. In a text .gltf they are checked
// first: whole numbers from 0 up.
void check_sizes_are_counts(const fs::path& file) {
  std::ifstream in(file);
  const nlohmann::json doc = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (!doc.is_object()) return;  // tinygltf reports what is wrong with it
  const char* sized[] = {"accessors", "bufferViews", "buffers"};
  for (const char* list : sized) {
    const auto items = doc.find(list);
    if (items == doc.end() || !items->is_array()) continue;
    for (std::size_t i = 0; i < items->size(); ++i)
      for (const char* key : {"byteOffset", "byteLength", "byteStride", "count"}) {
        const auto value = (*items)[i].find(key);
        if (value != (*items)[i].end() && !value->is_number_unsigned())
          throw InputError(file, std::string(list) + "[" + std::to_string(i) + "]." + key +
                                     " must be a whole number from 0, not " + value->dump());
      }
  }
}

}  // namespace

Mesh load_gltf_mesh(const fs::path& file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) throw InputError(file, "glTF file not found");
  if (file.extension() == ".gltf") check_sizes_are_counts(file);
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(load_image_naming_uri, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  const bool binary = file.extension() == ".glb" || file.extension() == ".GLB";
  const bool ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, file.string())
                         : loader.LoadASCIIFromFile(&model, &err, &warn, file.string());
  if (!ok || !err.empty()) {
    while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
    throw InputError(file, "cannot load glTF: " + (err.empty() ? std::string("unknown error") : json_error_text(err)));
  }
  Mesh mesh;
  for (std::size_t t = 0; t < model.textures.size(); ++t)
    mesh.textures.push_back(decode_texture(file, model, int(t)));
  for (const tinygltf::Material& m : model.materials) {
    const tinygltf::PbrMetallicRoughness& pbr = m.pbrMetallicRoughness;
    Material mat;
    if (pbr.baseColorFactor.size() == 4)
      mat.base_color = glm::vec4(pbr.baseColorFactor[0], pbr.baseColorFactor[1],
                                 pbr.baseColorFactor[2], pbr.baseColorFactor[3]);
    mat.metallic = float(pbr.metallicFactor);
    mat.roughness = float(pbr.roughnessFactor);
    // glTF's own ranges; NaN fails them too.
    const auto in_unit = [](double v) { return v >= 0.0 && v <= 1.0; };
    bool factors_ok = in_unit(pbr.metallicFactor) && in_unit(pbr.roughnessFactor);
    for (double v : pbr.baseColorFactor) factors_ok = factors_ok && in_unit(v);
    if (!factors_ok)
      throw InputError(file, "material \"" + m.name + "\": colour, metallic and roughness factors must be in [0, 1]");
    mat.texture = pbr.baseColorTexture.index;
    if (mat.texture >= int(mesh.textures.size()))
      throw InputError(file, "material \"" + m.name + "\": baseColorTexture index out of range");
    mesh.materials.push_back(mat);
  }
  mesh.materials.push_back(Material{});  // the default, for primitives without a material

  Flattener flatten(file, model, mesh);
  if (!model.scenes.empty()) {
    const int scene = model.defaultScene >= 0 ? model.defaultScene : 0;
    if (scene >= int(model.scenes.size())) throw InputError(file, "default scene index out of range");
    for (int root : model.scenes[scene].nodes) flatten.node(root, glm::mat4(1.0f), 0);
  } else {
    // No scenes: every node that is nobody's child is a root.
    std::vector<bool> is_child(model.nodes.size(), false);
    for (const tinygltf::Node& n : model.nodes)
      for (int c : n.children)
        if (c >= 0 && c < int(is_child.size())) is_child[c] = true;
    for (std::size_t i = 0; i < model.nodes.size(); ++i)
      if (!is_child[i]) flatten.node(int(i), glm::mat4(1.0f), 0);
  }
  if (mesh.triangle_count() == 0) throw InputError(file, "the scene has no triangles");
  for (const glm::vec3& p : mesh.positions)
    if (!usable_number(p.x) || !usable_number(p.y) || !usable_number(p.z))
      throw InputError(file, "a vertex lies beyond 1e6 once its node transforms are applied");
  return mesh;
}

}  // namespace splat::raytrace
