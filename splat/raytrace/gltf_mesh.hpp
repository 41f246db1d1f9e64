#pragma once
// A glTF 2.0 file flattened into one world-space triangle mesh: node transforms baked into
// the vertices, every primitive's material kept by index, textures decoded to linear float.
// The subset read is the one our scenes use: triangle primitives, uint16 /
// uint32 / no indices, float POSITION / NORMAL / TEXCOORD_0, pbrMetallicRoughness materials
// with an optional base-colour PNG texture; .gltf (embedded or external buffers) or .glb.
// Not read: base-colour alpha (everything renders opaque), samplers (textures always wrap
// with REPEAT and filter bilinearly), texture transforms, other texture slots, extensions.
#include <cstdint>
#include <filesystem>
#include <vector>

#include <glm/glm.hpp>

namespace splat::raytrace {

// Base colour texture in linear RGB (decoded from sRGB) with linear alpha.
struct Texture {
  int width = 0, height = 0;
  std::vector<glm::vec4> texels;  // [height, width], row 0 at v = 0
};

// glTF's default material when a primitive has none: base colour 1, metallic 1, roughness 1
// (the glTF 2.0 spec's defaults, kept as written so files render the way other viewers show them).
struct Material {
  glm::vec4 base_color{1.0f};
  int texture = -1;  // index into Mesh::textures, -1 for none
  float metallic = 1.0f;
  float roughness = 1.0f;
};

struct Mesh {
  std::vector<glm::vec3> positions;  // [V] world space
  std::vector<glm::vec3> normals;    // [V] world space, unit
  std::vector<glm::vec2> uvs;        // [V] (0, 0) where the primitive has no TEXCOORD_0
  std::vector<std::uint32_t> indices;  // [T, 3]
  std::vector<int> triangle_material;  // [T] index into materials
  std::vector<Material> materials;     // the file's materials, then the default one last
  std::vector<Texture> textures;       // one per glTF texture
  std::size_t triangle_count() const { return triangle_material.size(); }
};

// Loads `file` (.gltf or .glb). Throws InputError naming the file for a missing or malformed
// file, an image that does not decode, or anything outside the subset above.
Mesh load_gltf_mesh(const std::filesystem::path& file);

}  // namespace splat::raytrace
