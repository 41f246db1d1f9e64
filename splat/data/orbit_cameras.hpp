#pragma once
// Camera rigs and writing them as Blender / NeRF-synthetic transforms JSON, so the data we
// make (the demo model's views, splat-scene datasets) reads back through load_transforms.
#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "splat/core/camera.hpp"

namespace splat {

// `count` cameras evenly spaced in azimuth on a circle around `target` (world z is up),
// at `elevation_radians` above the horizontal, all looking at the target.
struct OrbitRig {
  int count = 8;
  float radius = 4.0f;
  float elevation_radians = 0.4f;
  float fov_x_radians = 0.7f;
  int width = 400, height = 400;
  glm::vec3 target{0.0f};
};
std::vector<Camera> orbit_cameras(const OrbitRig& rig);

// Camera looking from `eye` at `target` with world `up`, internal (OpenCV) axes.
Camera look_at(const glm::vec3& eye, const glm::vec3& target, const glm::vec3& up, float fx,
               float fy, int width, int height);

// Writes cameras as transforms JSON (camera_angle_x plus fl_x/fl_y/cx/cy/w/h of the first,
// and per frame file_path, the OpenGL camera-to-world transform_matrix, and the intrinsics of a
// frame whose own differ from the first's), atomically.
// `file_paths[i]` is frame i's file_path, e.g. "./test/r_0".
void write_transforms(const std::filesystem::path& file, const std::vector<Camera>& cameras,
                      const std::vector<std::string>& file_paths);

}  // namespace splat
