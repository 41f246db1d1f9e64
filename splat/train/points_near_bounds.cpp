#include "splat/train/points_near_bounds.hpp"

#include <algorithm>
#include <cmath>

namespace splat {

namespace {

// The depth of `p` in `camera` when its centre projects inside the frame, else 0.
float depth_in_frame(const Camera& camera, const glm::vec3& p) {
  const glm::vec3 q = camera.camera_from_world(p);
  if (!(q.z > 1e-6f)) return 0.0f;
  const float u = camera.fx * q.x / q.z + camera.cx, v = camera.fy * q.y / q.z + camera.cy;
  if (!(u >= 0 && u < float(camera.width) && v >= 0 && v < float(camera.height))) return 0.0f;
  return q.z;
}

}  // namespace

std::vector<CameraNearBound> points_near_bounds(const Dataset& dataset) {
  std::vector<CameraNearBound> bounds;
  if (!dataset.points) return bounds;
  const PointCloud& points = *dataset.points;
  std::vector<float> depths;
  for (const DatasetView& view : dataset.train) {
    depths.clear();
    for (std::size_t i = 0; i < points.size(); ++i) {
      const glm::vec3 p(points.positions[3 * i], points.positions[3 * i + 1], points.positions[3 * i + 2]);
      if (const float z = depth_in_frame(view.camera, p); z > 0) depths.push_back(z);
    }
    if (depths.size() < kMinPointsForNearBound) continue;
    const auto nth = depths.begin() + std::ptrdiff_t(std::floor(kNearPointQuantile * float(depths.size())));
    std::nth_element(depths.begin(), nth, depths.end());
    bounds.push_back({view.camera, *nth});
  }
  return bounds;
}

bool in_front_of_points(const std::vector<CameraNearBound>& bounds, const glm::vec3& position, float factor) {
  for (const CameraNearBound& bound : bounds) {
    const float z = depth_in_frame(bound.camera, position);
    if (z > 0 && z < factor * bound.near_depth) return true;
  }
  return false;
}

}  // namespace splat
