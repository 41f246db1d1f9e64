#pragma once
// Blender / NeRF-synthetic camera files (transforms_*.json).
#include <filesystem>
#include <string>
#include <vector>

#include "splat/core/camera.hpp"

namespace splat {

struct CameraFrame {
  std::string name;                   // base name of file_path, e.g. "r_0"
  std::filesystem::path image_path;   // file_path resolved against the JSON's folder; the
                                      // ".png" extension is added when file_path has none
  Camera camera;                      // internal convention (camera.hpp)
};

struct TransformsOptions {
  // Output size. 0 means: the JSON's "w"/"h" if given, else the size of the first frame's
  // image if it exists, else 800 x 800. Intrinsics are scaled from the native size.
  int width = 0, height = 0;
};

// Reads intrinsics from camera_angle_x (and camera_angle_y if present), or fl_x/fl_y/cx/cy
// with w/h (file-level or per-frame), and every frame's transform_matrix (camera-to-world,
// OpenGL axes). Throws InputError naming the file for unreadable or malformed JSON, no
// frames, a missing or non-numeric field, a non-finite matrix, or missing intrinsics.
std::vector<CameraFrame> load_transforms(const std::filesystem::path& file,
                                         const TransformsOptions& options = {});

}  // namespace splat
