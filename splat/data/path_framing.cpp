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
// and the images' up vectors lean towards that normal on average by more than this cosine
// (cameras pitched less than about 70 degrees, not rolled over).
constexpr float kMinUprightness = 0.3f;
// Otherwise it takes the normal of the camera centres' flattest direction when their variance
// across it is under kMaxRingFlatness times the next one, and signs it by the images' up when
// their cosine exceeds kMinUpAgreement.
constexpr double kMaxRingFlatness = 0.25;
constexpr float kMinUpAgreement = 0.3f;

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

glm::vec3 capture_up(std::span<const Camera> cameras, const std::optional<glm::vec3>& focus, const glm::vec3& fallback) {
  glm::vec3 mean_up(0.0f), mean_position(0.0f);
  Eigen::Matrix3d rights = Eigen::Matrix3d::Zero();  // mean of right·rightᵀ
  for (const Camera& camera : cameras) {
    // Rows of R are the camera's axes in world coordinates (glm is [col][row]): row 0 is its
    // right, row 1 its down.
    const glm::mat3& r = camera.camera_from_world_rotation;
    mean_up -= glm::vec3(r[0][1], r[1][1], r[2][1]);
    mean_position += camera.center_in_world() / float(cameras.size());
    const Eigen::Vector3d right(r[0][0], r[1][0], r[2][0]);
    rights += right * right.transpose() / double(cameras.size());
  }
  if (!(glm::length(mean_up) > 1e-6f)) return fallback;
  const glm::vec3 summed_up = mean_up / float(cameras.size());  // mean of the image ups
  mean_up = glm::normalize(mean_up);
  const auto signed_like = [](const Eigen::Vector3d& v, const glm::vec3& reference) {
    const glm::vec3 up = glm::normalize(glm::vec3{float(v[0]), float(v[1]), float(v[2])});
    return glm::dot(up, reference) < 0.0f ? -up : up;
  };
  // 1. Level cameras: their right vectors span a plane, whose normal is up.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> level(rights);
  const Eigen::Vector3d right_spread = level.eigenvalues();  // ascending
  if (right_spread[1] > kMinRightSpread && right_spread[1] > kRightSpreadRatio * right_spread[0]) {
    // ... and the images are upright about it: a short arc of turned images' right vectors
    // spans a plane too, but their up vectors then lie across its normal.
    const glm::vec3 level_up = signed_like(level.eigenvectors().col(0), mean_up);
    if (glm::dot(summed_up, level_up) > kMinUprightness) return level_up;
  }
  // 2. Otherwise (images stored turned by 90 degrees, as phones do, or held at any roll):
  // cameras walked round an object lie on a ring or a cap round its vertical axis, the
  // normal of the plane they are flattest in. Only when they look at one point: a
  // forward-facing capture's cameras lie across their view instead.
  if (!focus) return mean_up;
  Eigen::Matrix3d positions = Eigen::Matrix3d::Zero();
  for (const Camera& camera : cameras) {
    const glm::vec3 d = camera.center_in_world() - mean_position;
    const Eigen::Vector3d offset(d.x, d.y, d.z);
    positions += offset * offset.transpose() / double(cameras.size());
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> ring(positions);
  const Eigen::Vector3d ring_spread = ring.eigenvalues();
  if (!(ring_spread[1] > 0.0 && ring_spread[0] < kMaxRingFlatness * ring_spread[1])) return mean_up;
  const glm::vec3 normal = signed_like(ring.eigenvectors().col(0), mean_up);
  // The sign: the images' own up when it leans clearly one way, else the side the cameras
  // stand on (people photograph objects from above).
  if (std::abs(glm::dot(normal, mean_up)) > kMinUpAgreement) return normal;
  return glm::dot(normal, mean_position - *focus) < 0.0f ? -normal : normal;
  return mean_up;
}

PathFraming frame_from_cameras(std::span<const Camera> cameras, const AxisAlignedBox& content) {
  if (cameras.empty()) throw ArgumentError("frame_from_cameras: no cameras");
  PathFraming framing;
  const std::optional<CameraRig> rig = converging_rig(cameras);
  framing.center = rig ? rig->focus : 0.5f * (content.lo + content.hi);
  framing.up = capture_up(cameras, rig ? std::optional(rig->focus) : std::nullopt, glm::vec3(0, 0, 1));
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
