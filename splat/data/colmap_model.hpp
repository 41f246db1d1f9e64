#pragma once
// COLMAP sparse models (cameras, images, points3D) in COLMAP's text or binary form, as
// written by COLMAP itself. Only what a splatting dataset needs is kept: intrinsics, poses,
// image names and the 3D points with their colours (no 2D observations, no tracks).
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace splat {

// COLMAP's camera model ids (its enum values, which cameras.bin stores).
enum class ColmapCameraModel : int {
  kSimplePinhole = 0,  // f, cx, cy
  kPinhole = 1,        // fx, fy, cx, cy
  kSimpleRadial = 2,   // f, cx, cy, k
  kRadial = 3,         // f, cx, cy, k1, k2
  kOpenCv = 4,         // fx, fy, cx, cy, k1, k2, p1, p2
};

// COLMAP's name for a model id, including ones we do not support ("FULL_OPENCV"), or
// "model id N" for an id COLMAP does not define either.
std::string colmap_model_name(int model_id);
// How many parameters a supported model has.
int colmap_parameter_count(ColmapCameraModel model);

struct ColmapCamera {
  std::uint32_t id = 0;
  ColmapCameraModel model = ColmapCameraModel::kPinhole;
  int width = 0, height = 0;
  std::vector<double> params;  // in COLMAP's order for `model`
};

struct ColmapImage {
  std::uint32_t id = 0;
  std::array<double, 4> quaternion{1, 0, 0, 0};  // (w, x, y, z), world-to-camera rotation
  std::array<double, 3> translation{0, 0, 0};    // world-to-camera, OpenCV axes
  std::uint32_t camera_id = 0;
  std::string name;  // relative to the images/ folder, e.g. "000.png"
};

struct ColmapModel {
  // The files read (the .bin or .txt of each), for messages about their contents.
  std::filesystem::path cameras_file, images_file, points_file;
  std::vector<ColmapCamera> cameras;  // file order
  std::vector<ColmapImage> images;    // file order
  std::vector<float> point_positions;  // [P, 3]
  std::vector<float> point_colors;     // [P, 3] in [0, 1] (COLMAP's 8-bit colour / 255)

  // The camera with `id`, or nullptr.
  const ColmapCamera* find_camera(std::uint32_t id) const;
};

// Reads `sparse_dir`/{cameras,images,points3D}.{bin,txt}, each file in binary form when the
// .bin exists, else text. Throws InputError naming the file for a missing file, a truncated
// or malformed one, an unsupported camera model, an image whose camera is not in cameras,
// duplicate ids, or an empty point cloud. Binary counts are checked against the file size
// before anything is allocated, so a corrupt header cannot ask for gigabytes.
ColmapModel read_colmap_model(const std::filesystem::path& sparse_dir);

// The pieces of read_colmap_model, one file each (the binary or text form by extension).
std::vector<ColmapCamera> read_colmap_cameras(const std::filesystem::path& file);
std::vector<ColmapImage> read_colmap_images(const std::filesystem::path& file);
void read_colmap_points(const std::filesystem::path& file, std::vector<float>& positions,
                        std::vector<float>& colors);

}  // namespace splat
