#pragma once
// A scene spec: the JSON file that says which glTF to render, from where, under which lights,
// into a dataset. Reading is strict: an unknown key or an impossible value
// is an InputError naming the spec file and the key. Format (// comments allowed):
//   {
//     "description": "what this scene tests",            optional
//     "gltf": "models/toy.gltf",                          relative to the spec file; .gltf or .glb
//     "cameras": {"rig": "orbit", "target": [0,0,0],     target optional (origin)
//                 "radius": 4.0,                          > 0
//                 "elevation_deg": [10, 60],              lo <= hi, both within [-89, 89]
//                 "fov_deg": 40,                          horizontal, in (0, 180)
//                 "width": 200, "height": 200,            1..4096
//                 "train": 60, "test": 12},               train >= 1, test >= 0
//     "lights": [{"type": "directional", "direction": [-0.3,-1,-0.5], "color": [1,1,1], "intensity": 2},
//                {"type": "point", "position": [2,3,2], "color": [1,1,1], "intensity": 20}],
//                                                         optional; color optional (white);
//                                                         point lights fall off as 1/r²
//     "ambient": [0.25, 0.25, 0.25],                      optional (0), >= 0
//     "background": null,                                 optional; null: transparent (alpha =
//                                                         coverage), or [r,g,b] in [0,1]: opaque
//     "samples_per_pixel": 16,                            optional (16), 1..1024, jittered
//     "seed": 0                                           optional (0)
//   }
// World up is +Y, as in glTF.
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace splat::raytrace {

// Cameras on a sphere around `target`, on a golden-angle spiral over an elevation band.
struct OrbitSpec {
  glm::vec3 target{0.0f};
  float radius = 4.0f;
  float elevation_lo_deg = 10.0f, elevation_hi_deg = 60.0f;  // within [-89, 89], lo <= hi
  float fov_x_deg = 40.0f;                                   // horizontal, in (0, 180)
  int width = 200, height = 200;                             // 1..4096
  int train = 60, test = 12;                                 // train >= 1, test >= 0
};

struct LightSpec {
  enum class Type { directional, point };
  Type type = Type::directional;
  glm::vec3 direction{0, -1, 0};  // directional: the direction light travels (normalised)
  glm::vec3 position{0.0f};       // point
  glm::vec3 color{1.0f};
  float intensity = 1.0f;         // point lights fall off as intensity / r^2
};

struct SceneSpec {
  std::filesystem::path spec_file;
  std::string description;
  std::filesystem::path gltf;  // resolved against the spec file's folder
  OrbitSpec cameras;
  std::vector<LightSpec> lights;
  glm::vec3 ambient{0.0f};
  std::optional<glm::vec3> background;  // none: transparent, alpha = coverage
  int samples_per_pixel = 16;           // 1..1024
  unsigned seed = 0;
};

// Reads and validates `spec_file` (comments allowed). Throws InputError naming the file.
SceneSpec load_scene_spec(const std::filesystem::path& spec_file);

}  // namespace splat::raytrace
