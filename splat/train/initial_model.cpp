#include "splat/train/initial_model.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "splat/core/camera_rig.hpp"
#include "splat/core/error.hpp"
#include "splat/gaussians/initialization.hpp"
#include "splat/gaussians/view_points.hpp"

namespace splat {
namespace {

void append(PointCloud& to, const PointCloud& from) {
  to.positions.insert(to.positions.end(), from.positions.begin(), from.positions.end());
  to.colors.insert(to.colors.end(), from.colors.begin(), from.colors.end());
}

// Random points in the views' frusta, plus the shell when the images show a background.
GaussianModel frusta_model(const Dataset& dataset, const SplatTrainingConfig& config, std::size_t count,
                           const glm::vec3& centre, float distance, InitialisationReport& report) {
  const bool shell = !background_left_out(dataset.train) && config.random_init_shell_fraction > 0;
  const std::size_t shell_count =
      shell ? std::max<std::size_t>(1, std::size_t(std::lround(double(count) * config.random_init_shell_fraction)))
            : 0;
  report.kind = "frusta";
  report.centre = centre;
  report.distance = distance;
  report.near = config.random_init_near * distance;
  report.far = config.random_init_far * distance;
  std::mt19937 rng(config.seed);
  PointCloud cloud;
  if (shell_count > 0) {
    // About the count asked for; never more, so a Gaussian budget holds.
    cloud = evenly_subsampled(background_shell(dataset.train, centre, report.far, std::min(shell_count, count)),
                              std::min(shell_count, count));
    report.shell_radius = report.far;
    report.shell_points = cloud.size();
  }
  // The shell takes what the views see of the sphere; the frusta the rest of the count.
  const std::size_t frustum_count = count - std::min(count, cloud.size());
  if (frustum_count > 0) append(cloud, frustum_points(dataset.train, frustum_count, report.near, report.far,
                                                         config.random_init_depth_candidates, rng));
  report.frustum_points = frustum_count;
  return initialize_from_points(cloud, config.sh_degree);
}

}  // namespace

nlohmann::json to_json(const InitialisationReport& r) {
  nlohmann::json j{{"kind", r.kind}};
  if (r.kind == "cube") {
    j["centre"] = {r.centre.x, r.centre.y, r.centre.z};
    j["half_extent"] = r.half_extent;
    if (r.distance > 0) j["camera_distance"] = r.distance;
  } else if (r.kind == "frusta") {
    j["centre"] = {r.centre.x, r.centre.y, r.centre.z};
    j["camera_distance"] = r.distance;
    j["near"] = r.near;
    j["far"] = r.far;
    j["frustum_points"] = r.frustum_points;
    j["shell_points"] = r.shell_points;
    j["shell_radius"] = r.shell_radius;
  }
  return j;
}

GaussianModel initial_model(const Dataset& dataset, const SplatTrainingConfig& config,
                            InitialisationReport* report) {
  InitialisationReport local;
  InitialisationReport& r = report ? *report : local;
  r = {};
  validate(config);
  const std::size_t budget = config.density.max_gaussians;
  if (dataset.points && dataset.points->size() > 0) {
    r.kind = "points";
    return initialize_from_points(budget > 0 ? evenly_subsampled(*dataset.points, budget) : *dataset.points,
                                  config.sh_degree);
  }
  const std::size_t count = budget > 0 ? std::min(config.random_init_points, budget) : config.random_init_points;
  if (config.random_init_half_extent > 0) {
    r.kind = "cube";
    r.half_extent = config.random_init_half_extent;
    return initialize_random(count, config.random_init_half_extent, config.seed, config.sh_degree);
  }

  const std::vector<Camera> cameras = cameras_of(dataset.train);
  const std::optional<CameraRig> rig = converging_rig(cameras);
  if (rig && rig->seen_radius > 0 && background_left_out(dataset.train)) {
    r.kind = "cube";
    r.centre = rig->focus;
    r.distance = rig->distance;
    r.half_extent = rig->seen_radius;
    GaussianModel model = initialize_random(count, rig->seen_radius, config.seed, config.sh_degree);
    // Moved after the scales are set: they depend only on the points' spacing.
    for (std::size_t i = 0; i < model.size(); ++i)
      for (int a = 0; a < 3; ++a) model.means[3 * i + a] += rig->focus[a];
    return model;
  }
  if (rig) return frusta_model(dataset, config, count, rig->focus, rig->distance, r);
  return frusta_model(dataset, config, count, mean_camera_centre(dataset.train), dataset.scene_extent, r);
}

}  // namespace splat
