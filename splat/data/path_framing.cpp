#include "splat/data/path_framing.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>

#include "splat/core/camera_rig.hpp"
#include "splat/core/error.hpp"

namespace splat {
namespace {

// A box thinner than this still gets a ball of this radius, so a single point (or a flat
// sheet seen edge-on) does not put the camera at distance zero.
constexpr float kMinFramedRadius = 1e-3f;

// capture_up trusts the cameras' right vectors when they spread over a plane: the second
// smallest eigenvalue of their scatter (a mean of unit outer products, so the eigenvalues sum
// to 1) is at least kMinRightSpread (right vectors some 10 degrees apart) and
// kRightSpreadRatio times the smallest (the cameras' roll is small against that spread).
constexpr double kMinRightSpread = 0.01;
constexpr double kRightSpreadRatio = 10.0;

// The first of these directions not nearly along `up`, made perpendicular to it: frame 0 of a
// path looks from the front when world z (the Blender scenes' -y front) or world y is up.
glm::vec3 default_start(const glm::vec3& up) {
  for (const glm::vec3 candidate : {glm::vec3(0, -1, 0), glm::vec3(0, 0, 1), glm::vec3(1, 0, 0)}) {
    if (std::abs(glm::dot(candidate, up)) < 0.9f)
      return glm::normalize(candidate - glm::dot(candidate, up) * up);
  }
  return {1, 0, 0};  // unreachable: no unit vector is within 26 degrees of all three
}

// The value below which `fraction` of the total weight lies, over (value, weight) pairs
// sorted by value.
float weighted_quantile(const std::vector<std::pair<float, float>>& sorted, double total, double fraction) {
  double below = 0;
  for (const auto& [value, weight] : sorted) {
    below += weight;
    if (below >= fraction * total) return value;
  }
  return sorted.back().first;
}

}  // namespace

std::optional<AxisAlignedBox> robust_box(std::span<const float> xyz, std::span<const float> weights, float tail) {
  const std::size_t count = xyz.size() / 3;
  if (!weights.empty() && weights.size() != count)
    throw ArgumentError("robust_box: one weight per point, or none");
  if (!(tail >= 0.0f && tail < 0.5f)) throw ArgumentError("robust_box: tail must be in [0, 0.5)");
  AxisAlignedBox box{};
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<std::pair<float, float>> values;  // (coordinate, weight) of the usable points
    values.reserve(count);
    double total = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const glm::vec3 p(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
      const float w = weights.empty() ? 1.0f : weights[i];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !(w > 0.0f)) continue;
      values.emplace_back(p[axis], w);
      total += w;
    }
    if (values.empty()) return std::nullopt;
    // Sorting the pairs, weight as the tie-break, makes the result independent of point order.
    std::sort(values.begin(), values.end());
    box.lo[axis] = weighted_quantile(values, total, tail);
    box.hi[axis] = weighted_quantile(values, total, 1.0 - tail);
  }
  return box;
}

PathFraming frame_box(const AxisAlignedBox& box, const glm::vec3& up, float aspect) {
  PathFraming framing;
  framing.center = 0.5f * (box.lo + box.hi);
  framing.up = glm::normalize(up);
  framing.start = default_start(framing.up);
  framing.elevation = kDefaultPathElevation;
  framing.fov_y = kDefaultPathFovY;
  const float radius = std::max(0.5f * glm::length(box.hi - box.lo), kMinFramedRadius);
  // The ball of that radius fills the narrower half field of view: sin(half) = r / distance.
  const float half_narrow = std::atan(std::min(aspect, 1.0f) * std::tan(0.5f * framing.fov_y));
  framing.distance = radius / std::sin(half_narrow);
  return framing;
}

glm::vec3 capture_up(std::span<const Camera> cameras, const glm::vec3& fallback) {
  glm::vec3 mean_up(0.0f);
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();  // mean of right·rightᵀ
  for (const Camera& camera : cameras) {
    // Rows of R are the camera's axes in world coordinates (glm is [col][row]): row 0 is its
    // right, row 1 its down.
    const glm::mat3& r = camera.camera_from_world_rotation;
    mean_up -= glm::vec3(r[0][1], r[1][1], r[2][1]);
    const Eigen::Vector3d right(r[0][0], r[1][0], r[2][0]);
    scatter += right * right.transpose() / double(cameras.size());
  }
  if (!(glm::length(mean_up) > 1e-6f)) return fallback;
  mean_up = glm::normalize(mean_up);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  const Eigen::Vector3d spread = solver.eigenvalues();  // ascending
  if (!(spread[1] > kMinRightSpread && spread[1] > kRightSpreadRatio * spread[0])) return mean_up;
  const Eigen::Vector3d normal = solver.eigenvectors().col(0);
  const glm::vec3 up = glm::normalize(glm::vec3{float(normal[0]), float(normal[1]), float(normal[2])});
  return glm::dot(up, mean_up) < 0.0f ? -up : up;
}

PathFraming frame_from_cameras(std::span<const Camera> cameras, const AxisAlignedBox& content) {
  if (cameras.empty()) throw ArgumentError("frame_from_cameras: no cameras");
  PathFraming framing;
  const std::optional<CameraRig> rig = converging_rig(cameras);
  framing.center = rig ? rig->focus : 0.5f * (content.lo + content.hi);
  framing.up = capture_up(cameras, glm::vec3(0, 0, 1));
  double distance = 0, elevation = 0;
  for (const Camera& camera : cameras) {
    const glm::vec3 offset = camera.center_in_world() - framing.center;
    const float length = std::max(glm::length(offset), kMinFramedRadius);
    distance += length;
    elevation += std::asin(std::clamp(glm::dot(offset, framing.up) / length, -1.0f, 1.0f));
  }
  framing.distance = float(distance / double(cameras.size()));
  framing.elevation = float(elevation / double(cameras.size()));
  const glm::vec3 first = cameras.front().center_in_world() - framing.center;
  const glm::vec3 horizontal = first - glm::dot(first, framing.up) * framing.up;
  framing.start = glm::length(horizontal) > 1e-6f * std::max(1.0f, glm::length(first))
                      ? glm::normalize(horizontal)
                      : default_start(framing.up);
  framing.fov_y = 2.0f * std::atan(cameras.front().tan_half_fov_y());
  return framing;
}

}  // namespace splat
