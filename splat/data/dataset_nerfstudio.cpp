// nerfstudio folders: one transforms.json for every view (what ns-process-data writes, and
// what many captures are shared as), with intrinsics for the file or per frame, OpenCV lens
// distortion, optional per-image masks and an optional point cloud. The split is ours, as for
// COLMAP data.
#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "splat/core/error.hpp"
#include "splat/core/json_file.hpp"
#include "splat/data/dataset_loading.hpp"
#include "splat/data/point_cloud_ply.hpp"
#include "splat/data/transforms_json.hpp"

namespace splat::dataset_detail {

namespace fs = std::filesystem;

namespace {

// The point cloud "ply_file_path" names (ns-process-data writes sparse_pc.ply, COLMAP's points
// in the transforms' world), or none: the Gaussians then start as for Blender data.
std::optional<PointCloud> read_points(const fs::path& file) {
  const nlohmann::json root = read_json_file(file, "transforms file");
  const auto it = root.find("ply_file_path");
  if (it == root.end()) return std::nullopt;
  if (!it->is_string() || it->get_ref<const std::string&>().empty())
    throw InputError(file, "\"ply_file_path\" must be a non-empty string");
  PointCloud cloud = read_point_cloud_ply((file.parent_path() / it->get<std::string>()).lexically_normal());
  if (cloud.size() == 0) throw InputError(file, "\"ply_file_path\" names a point cloud without points");
  return cloud;
}

}  // namespace

Dataset load_nerfstudio(const fs::path& folder, const DatasetOptions& options) {
  const fs::path file = folder / "transforms.json";
  std::vector<CameraFrame> frames = load_transforms(file);
  // Name order decides the split, whatever order the file lists the frames in.
  std::stable_sort(frames.begin(), frames.end(),
                   [](const CameraFrame& a, const CameraFrame& b) { return a.image_path < b.image_path; });

  std::vector<ImageSize> sizes;
  for (const CameraFrame& frame : frames) sizes.push_back({frame.camera.width, frame.camera.height});
  const int downscale = chosen_downscale(sizes, options);
  check_dataset_fits_in_memory(folder, sizes, downscale);

  std::vector<DatasetView> views(frames.size());
  for_each_in_parallel(frames.size(), [&](std::size_t i) {
    views[i].name = frames[i].name;
    load_view(view_source(frames[i], file), downscale, options.background, views[i]);
  });
  Dataset dataset = split_by_holdout(std::move(views), options, file);
  dataset.downscale = downscale;
  dataset.points = read_points(file);
  return dataset;
}

}  // namespace splat::dataset_detail
