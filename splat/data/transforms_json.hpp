#pragma once
// Camera files in the transforms layout: Blender / NeRF-synthetic (transforms_*.json) and
// nerfstudio's transforms.json (lens distortion, per-image masks).
#include <filesystem>
#include <string>
#include <vector>

#include "splat/core/camera.hpp"
#include "splat/data/undistort.hpp"

namespace splat {

struct CameraFrame {
  std::string name;                   // base name of file_path, e.g. "r_0"
  std::filesystem::path image_path;   // file_path resolved against the JSON's folder; the
                                      // ".png" extension is added when file_path has none
  Camera camera;                      // internal convention (camera.hpp)
  LensDistortion distortion;          // nerfstudio's k1, k2, p1, p2 (OPENCV); zero: a pinhole
  std::filesystem::path mask_path;    // nerfstudio's "mask_path" resolved likewise; empty: none
};

struct TransformsOptions {
  // Output size. 0 means: the JSON's "w"/"h" if given, else the size of the first frame's
  // image if it exists, else 800 x 800. Intrinsics are scaled from the native size
  // (Camera::resized). Give both or neither: one alone is an ArgumentError.
  int width = 0, height = 0;
};

// Reads intrinsics from camera_angle_x (and camera_angle_y if present, else fy = fx), or
// fl_x/fl_y/cx/cy with w/h; each key may sit at file level or in a frame, the frame's value
// winning (nerfstudio style), and fl_x wins over camera_angle_x. cx, cy default to the image
// centre (W/2, H/2). "camera_model" may be PINHOLE, SIMPLE_PINHOLE or OPENCV (nerfstudio's
// default), with k1, k2, p1, p2 (default 0; k3, k4 must be 0) likewise frame or file level;
// other camera models are refused by name. A frame's "mask_path" names its mask image. Reads
// every frame's transform_matrix (camera-to-world, OpenGL axes), which must be rigid. Throws InputError naming the file for unreadable or malformed JSON, no
// frames, a missing or non-numeric field, a non-finite or non-rigid matrix, missing
// intrinsics, or implausible sizes and focal lengths.
std::vector<CameraFrame> load_transforms(const std::filesystem::path& file,
                                         const TransformsOptions& options = {});

}  // namespace splat
