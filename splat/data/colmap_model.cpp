#include "splat/data/colmap_model.hpp"

#include <cmath>
#include <set>
#include <unordered_set>

#include "splat/core/error.hpp"
#include "splat/core/image.hpp"
#include "splat/data/colmap_readers.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

// COLMAP's model names in id order (src/colmap/sensor/models.h); the ones past OPENCV are
// listed only so that an unsupported model is reported by name.
constexpr const char* kModelNames[] = {
    "SIMPLE_PINHOLE", "PINHOLE",          "SIMPLE_RADIAL",         "RADIAL",
    "OPENCV",         "OPENCV_FISHEYE",   "FULL_OPENCV",           "FOV",
    "SIMPLE_RADIAL_FISHEYE", "RADIAL_FISHEYE", "THIN_PRISM_FISHEYE", "RAD_TAN_THIN_PRISM_FISHEYE",
};
constexpr int kModelNameCount = int(std::size(kModelNames));
constexpr int kSupportedModelCount = 5;  // ids 0 to 4


// Binary is COLMAP's default output and exact; text is the fallback.
fs::path model_file(const fs::path& sparse_dir, const std::string& stem) {
  std::error_code ec;
  const fs::path bin = sparse_dir / (stem + ".bin");
  if (fs::is_regular_file(bin, ec)) return bin;
  const fs::path txt = sparse_dir / (stem + ".txt");
  if (fs::is_regular_file(txt, ec)) return txt;
  throw InputError(sparse_dir / (stem + ".bin"),
                   "missing: a COLMAP model needs " + stem + ".bin or " + stem + ".txt in " +
                       sparse_dir.string());
}

bool is_binary(const fs::path& file) { return file.extension() == ".bin"; }

void check_exists(const fs::path& file) {
  std::error_code ec;
  if (!fs::exists(file, ec)) throw InputError(file, "file does not exist");
  if (!fs::is_regular_file(file, ec)) throw InputError(file, "is not a regular file");
}

}  // namespace

std::string colmap_model_name(int model_id) {
  if (model_id >= 0 && model_id < kModelNameCount) return kModelNames[model_id];
  return "model id " + std::to_string(model_id);
}

int colmap_parameter_count(ColmapCameraModel model) {
  switch (model) {
    case ColmapCameraModel::kSimplePinhole: return 3;
    case ColmapCameraModel::kPinhole: return 4;
    case ColmapCameraModel::kSimpleRadial: return 4;
    case ColmapCameraModel::kRadial: return 5;
    case ColmapCameraModel::kOpenCv: return 8;
  }
  return 0;
}

const ColmapCamera* ColmapModel::find_camera(std::uint32_t id) const {
  for (const ColmapCamera& camera : cameras)
    if (camera.id == id) return &camera;
  return nullptr;
}

namespace colmap_detail {

int model_id_from_name(std::string_view name) {
  for (int id = 0; id < kModelNameCount; ++id)
    if (name == kModelNames[id]) return id;
  return -1;
}

ColmapCameraModel supported_model(const fs::path& file, const std::string& where, int model_id) {
  if (model_id >= 0 && model_id < kSupportedModelCount) return ColmapCameraModel(model_id);
  throw InputError(file, where + ": unsupported camera model " + colmap_model_name(model_id) +
                             " (supported: SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL, RADIAL, "
                             "OPENCV)");
}

void check_camera(const fs::path& file, const std::string& where, const ColmapCamera& camera) {
  if (const std::string problem = camera_size_problem(camera.width, camera.height); !problem.empty())
    throw InputError(file, where + ": image size " + std::to_string(camera.width) + " x " +
                               std::to_string(camera.height) + ": " + problem);
  for (double p : camera.params)
    if (!std::isfinite(p)) throw InputError(file, where + ": non-finite camera parameter");
  // Every supported model starts with its focal length(s); PINHOLE and OPENCV have two.
  const bool two_focals = camera.model == ColmapCameraModel::kPinhole ||
                          camera.model == ColmapCameraModel::kOpenCv;
  for (int i = 0; i < (two_focals ? 2 : 1); ++i)
    if (!(camera.params[i] > 0))
      throw InputError(file, where + ": focal length must be positive");
}

void check_image(const fs::path& file, const std::string& where, const ColmapImage& image) {
  double norm2 = 0;
  for (double q : image.quaternion) {
    if (!std::isfinite(q)) throw InputError(file, where + ": non-finite quaternion");
    norm2 += q * q;
  }
  // COLMAP normalises on use; a zero quaternion has no rotation to normalise to.
  if (!(norm2 > 1e-12)) throw InputError(file, where + ": zero quaternion");
  for (double t : image.translation)
    if (!std::isfinite(t)) throw InputError(file, where + ": non-finite translation");
  if (image.name.empty()) throw InputError(file, where + ": empty image name");
}

void check_point(const fs::path& file, const std::string& where, const double xyz[3]) {
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(xyz[a])) throw InputError(file, where + ": non-finite position");
}

}  // namespace colmap_detail

std::vector<ColmapCamera> read_colmap_cameras(const fs::path& file) {
  check_exists(file);
  std::vector<ColmapCamera> cameras = is_binary(file) ? colmap_detail::read_cameras_binary(file)
                                                      : colmap_detail::read_cameras_text(file);
  std::set<std::uint32_t> ids;
  for (const ColmapCamera& camera : cameras)
    if (!ids.insert(camera.id).second)
      throw InputError(file, "camera id " + std::to_string(camera.id) + " appears twice");
  if (cameras.empty()) throw InputError(file, "no cameras");
  return cameras;
}

std::vector<ColmapImage> read_colmap_images(const fs::path& file) {
  check_exists(file);
  std::vector<ColmapImage> images = is_binary(file) ? colmap_detail::read_images_binary(file)
                                                    : colmap_detail::read_images_text(file);
  std::set<std::uint32_t> ids;
  std::unordered_set<std::string> names;
  for (const ColmapImage& image : images) {
    if (!ids.insert(image.id).second)
      throw InputError(file, "image id " + std::to_string(image.id) + " appears twice");
    if (!names.insert(image.name).second)
      throw InputError(file, "image name " + image.name + " appears twice");
  }
  if (images.empty()) throw InputError(file, "no images");
  return images;
}

void read_colmap_points(const fs::path& file, std::vector<float>& positions,
                        std::vector<float>& colors) {
  check_exists(file);
  positions.clear();
  colors.clear();
  if (is_binary(file))
    colmap_detail::read_points_binary(file, positions, colors);
  else
    colmap_detail::read_points_text(file, positions, colors);
  // Gaussians are initialised from these points; a model without any cannot be trained.
  if (positions.empty()) throw InputError(file, "no 3D points: the point cloud is empty");
}

ColmapModel read_colmap_model(const fs::path& sparse_dir) {
  ColmapModel model;
  model.cameras_file = model_file(sparse_dir, "cameras");
  model.images_file = model_file(sparse_dir, "images");
  model.points_file = model_file(sparse_dir, "points3D");
  model.cameras = read_colmap_cameras(model.cameras_file);
  model.images = read_colmap_images(model.images_file);
  for (const ColmapImage& image : model.images)
    if (!model.find_camera(image.camera_id))
      throw InputError(model.images_file, "image " + image.name + " uses camera id " +
                                              std::to_string(image.camera_id) + ", which is not in " +
                                              model.cameras_file.filename().string());
  read_colmap_points(model.points_file, model.point_positions, model.point_colors);
  return model;
}

}  // namespace splat
