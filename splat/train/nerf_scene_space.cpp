#include "splat/train/nerf_scene_space.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "splat/core/camera_rig.hpp"

namespace splat {
namespace {

// Room round what the data shows, so its edges do not fall on the box's faces.
constexpr float kCameraBoxMargin = 1.1f;
constexpr float kPointBoxMargin = 0.05f;

AxisAlignedBox cube(const glm::vec3& centre, float half) {
  return {centre - glm::vec3(half), centre + glm::vec3(half)};
}

AxisAlignedBox point_box(const PointCloud& points) {
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const glm::vec3 q(points.positions[3 * i], points.positions[3 * i + 1], points.positions[3 * i + 2]);
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
  }
  const glm::vec3 margin = kPointBoxMargin * (hi - lo) + 1e-3f;
  return {lo - margin, hi + margin};
}

}  // namespace

SceneSpace scene_space_from_data(const Dataset& dataset, const AxisAlignedBox& fallback) {
  if (dataset.points && dataset.points->size() > 0) return {point_box(*dataset.points), false};
  const std::vector<Camera> cameras = cameras_of(dataset.train);
  const std::optional<CameraRig> rig = converging_rig(cameras);
  if (!rig) return {fallback, false};
  if (background_left_out(dataset.train)) {
    if (rig->seen_radius <= 0) return {fallback, false};
    return {cube(rig->focus, kCameraBoxMargin * rig->seen_radius), false};
  }
  float reach = 0;  // the largest per-axis offset of a camera from the focus
  for (const Camera& camera : cameras) {
    const glm::vec3 offset = glm::abs(camera.center_in_world() - rig->focus);
    reach = std::max({reach, offset.x, offset.y, offset.z});
  }
  if (!(reach > 0)) return {fallback, false};
  return {cube(rig->focus, kCameraBoxMargin * reach), true};
}

}  // namespace splat
