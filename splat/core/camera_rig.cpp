#include "splat/core/camera_rig.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace splat {
namespace {

// Axes closer to parallel than this leave the focus undetermined along them: the smallest
// eigenvalue of the mean of (I − d dᵀ) is sin² of about the axes' angular spread, and
// 1e-3 is a spread of about 2°.
constexpr double kMinAxisSpread = 1e-3;

}  // namespace

glm::vec3 optical_axis(const Camera& camera) {
  // Rᵀ·(0, 0, 1): the third row of R (glm stores columns).
  const glm::mat3& r = camera.camera_from_world_rotation;
  return glm::normalize(glm::vec3(r[0][2], r[1][2], r[2][2]));
}

bool in_view(const Camera& camera, const glm::vec3& p) {
  const glm::vec3 c = camera.camera_from_world(p);
  if (!(c.z > 0.0f)) return false;
  const float u = camera.fx * c.x / c.z + camera.cx, v = camera.fy * c.y / c.z + camera.cy;
  return u >= 0.0f && u <= float(camera.width) && v >= 0.0f && v <= float(camera.height);
}

std::optional<CameraRig> converging_rig(std::span<const Camera> cameras) {
  if (cameras.size() < 2) return std::nullopt;
  // The point p minimising Σ |(I − d dᵀ)(p − o)|², the squared distances to the axes
  // (o the centre, d the axis): (Σ (I − d dᵀ)) p = Σ (I − d dᵀ) o. In double, and divided
  // by the count so the eigenvalue test below does not depend on it.
  glm::dmat3 normal(0.0);
  glm::dvec3 rhs(0.0);
  const double n = double(cameras.size());
  for (const Camera& camera : cameras) {
    const glm::dvec3 d(optical_axis(camera)), o(camera.center_in_world());
    const glm::dmat3 projector = glm::dmat3(1.0) - glm::outerProduct(d, d);
    normal += projector / n;
    rhs += projector * o / n;
  }
  // The eigenvalues lie in [0, 1] (a mean of projectors), so the determinant is at most the
  // smallest: above the threshold, the axes pin the point down in every direction.
  if (!(glm::determinant(normal) > kMinAxisSpread)) return std::nullopt;
  CameraRig rig;
  rig.focus = glm::vec3(glm::inverse(normal) * rhs);

  std::vector<float> distances;
  std::size_t in_front = 0;
  float seen = std::numeric_limits<float>::infinity();
  for (const Camera& camera : cameras) {
    const glm::vec3 to_focus = rig.focus - camera.center_in_world();
    const float distance = glm::length(to_focus);
    distances.push_back(distance);
    const float cos_angle = distance > 0 ? glm::dot(to_focus, optical_axis(camera)) / distance : 1.0f;
    if (cos_angle > 0) ++in_front;
    const float angle = std::acos(std::clamp(cos_angle, -1.0f, 1.0f));
    const float half_fov = std::atan(std::min(camera.tan_half_fov_x(), camera.tan_half_fov_y()));
    seen = std::min(seen, distance * std::sin(std::max(0.0f, half_fov - angle)));
  }
  if (2 * in_front <= cameras.size()) return std::nullopt;
  std::nth_element(distances.begin(), distances.begin() + distances.size() / 2, distances.end());
  rig.distance = distances[distances.size() / 2];
  rig.seen_radius = seen;
  return rig;
}

}  // namespace splat
