// COLMAP folders: a sparse model (cameras, images, points3D) and the photos in images/.
// Poses are world-to-camera in OpenCV axes, the internal convention, and COLMAP puts the
// centre of the top-left pixel at (0.5, 0.5) as we do, so intrinsics carry over unchanged.
#include <algorithm>
#include <map>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "splat/core/error.hpp"
#include "splat/data/colmap_model.hpp"
#include "splat/data/dataset_loading.hpp"
#include "splat/data/undistort.hpp"
#include "splat/data/view_names.hpp"

namespace splat::dataset_detail {
namespace {

namespace fs = std::filesystem;

// Rotation matrix of the unit quaternion (w, x, y, z); COLMAP normalises before use too.
glm::mat3 rotation_from_quaternion(const std::array<double, 4>& q) {
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  const double w = q[0] / n, x = q[1] / n, y = q[2] / n, z = q[3] / n;
  const double rows[3][3] = {
      {1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
      {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
      {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)},
  };
  glm::mat3 r;  // glm is column-major: r[col][row]
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col) r[col][row] = float(rows[row][col]);
  return r;
}

// The pinhole part of a COLMAP camera and its lens distortion.
struct Intrinsics {
  Camera camera;  // intrinsics only
  LensDistortion distortion;
};

Intrinsics intrinsics_of(const ColmapCamera& c) {
  const std::vector<double>& p = c.params;
  Intrinsics out;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  switch (c.model) {
    case ColmapCameraModel::kSimplePinhole:
      fx = fy = p[0], cx = p[1], cy = p[2];
      break;
    case ColmapCameraModel::kPinhole:
      fx = p[0], fy = p[1], cx = p[2], cy = p[3];
      break;
    case ColmapCameraModel::kSimpleRadial:
      fx = fy = p[0], cx = p[1], cy = p[2];
      out.distortion.k1 = p[3];
      break;
    case ColmapCameraModel::kRadial:
      fx = fy = p[0], cx = p[1], cy = p[2];
      out.distortion.k1 = p[3], out.distortion.k2 = p[4];
      break;
    case ColmapCameraModel::kOpenCv:
      fx = p[0], fy = p[1], cx = p[2], cy = p[3];
      out.distortion = {p[4], p[5], p[6], p[7]};
      break;
  }
  out.camera.fx = float(fx), out.camera.fy = float(fy);
  out.camera.cx = float(cx), out.camera.cy = float(cy);
  out.camera.width = c.width, out.camera.height = c.height;
  return out;
}

}  // namespace

Dataset load_colmap(const fs::path& folder, const fs::path& sparse_dir,
                    const DatasetOptions& options) {
  ColmapModel model = read_colmap_model(sparse_dir);
  const fs::path image_dir = folder / "images";

  // Name order decides the split, whatever order the model file lists the images in.
  std::vector<const ColmapImage*> images;
  for (const ColmapImage& image : model.images) images.push_back(&image);
  std::sort(images.begin(), images.end(),
            [](const ColmapImage* a, const ColmapImage* b) { return a->name < b->name; });

  std::vector<ImageSize> sizes;
  for (const ColmapImage* image : images) {
    const ColmapCamera& camera = *model.find_camera(image->camera_id);
    sizes.push_back({camera.width, camera.height});
  }
  const int downscale = chosen_downscale(sizes, options);

  // Each distorting camera's pinhole image, less the border its lens does not cover: the
  // same for every view of the camera, so found once per camera.
  std::map<std::uint32_t, PixelRect> covered_regions;
  // (At the size the camera's photos are read at: reduced when beyond the pixel limit.)
  for (const ColmapCamera& camera : model.cameras) {
    const Intrinsics intrinsics = intrinsics_of(camera);
    if (intrinsics.distortion.is_identity()) continue;
    const Camera read_camera =
        reduced_camera(intrinsics.camera, read_reduction(camera.width, camera.height, downscale));
    const PixelRect covered = covered_region(read_camera, intrinsics.distortion);
    if (covered.width < read_camera.width / 2 || covered.height < read_camera.height / 2)
      throw InputError(model.cameras_file,
                       "camera " + std::to_string(camera.id) + ": its distortion leaves only " +
                           std::to_string(covered.width) + " x " + std::to_string(covered.height) + " of the " +
                           std::to_string(read_camera.width) + " x " + std::to_string(read_camera.height) +
                           " image covered");
    covered_regions[camera.id] = covered;
  }

  check_dataset_fits_in_memory(folder, sizes, downscale);

  std::vector<fs::path> image_names;
  for (const ColmapImage* image : images) image_names.push_back(image->name);
  const std::vector<std::string> names = view_names(image_names, model.images_file);
  std::vector<DatasetView> views(images.size());
  for_each_in_parallel(images.size(), [&](std::size_t i) {
    const ColmapImage& image = *images[i];
    ViewSource source;
    const Intrinsics intrinsics = intrinsics_of(*model.find_camera(image.camera_id));
    source.image = image_dir / image.name;
    source.camera = intrinsics.camera;
    source.camera.camera_from_world_rotation = rotation_from_quaternion(image.quaternion);
    source.camera.camera_from_world_translation =
        glm::vec3(float(image.translation[0]), float(image.translation[1]), float(image.translation[2]));
    source.distortion = intrinsics.distortion;
    if (auto covered = covered_regions.find(image.camera_id); covered != covered_regions.end())
      source.covered = covered->second;
    source.size_source = model.cameras_file.string() + " (camera " + std::to_string(image.camera_id) + ")";
    views[i].name = names[i];
    load_view(source, downscale, options.background, views[i]);
  });

  Dataset dataset = split_by_holdout(std::move(views), options, model.images_file);
  dataset.downscale = downscale;
  dataset.points = PointCloud{std::move(model.point_positions), std::move(model.point_colors)};
  return dataset;
}

}  // namespace splat::dataset_detail
