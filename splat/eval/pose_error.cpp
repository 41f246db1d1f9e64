#include "splat/eval/pose_error.hpp"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "splat/core/error.hpp"

namespace splat {

namespace {

Eigen::Matrix3d to_eigen(const glm::mat3& m) {
  Eigen::Matrix3d e;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) e(r, c) = m[c][r];  // glm is column-major: m[column][row]
  return e;
}

Eigen::Vector3d centre(const Camera& camera) {
  const glm::vec3 c = camera.center_in_world();
  return {c.x, c.y, c.z};
}

}  // namespace

PoseError pose_error(const std::vector<Camera>& estimated, const std::vector<Camera>& truth) {
  if (estimated.size() != truth.size())
    throw ArgumentError("pose error: " + std::to_string(estimated.size()) + " estimated cameras against " +
                        std::to_string(truth.size()) + " true ones");
  const int n = int(truth.size());
  if (n < 3) throw ArgumentError("pose error: needs at least 3 cameras");
  std::vector<Eigen::Vector3d> from(n), to(n);
  for (int i = 0; i < n; ++i) {
    from[i] = centre(estimated[i]);
    to[i] = centre(truth[i]);
  }
  // x_truth = s·G·x_estimated + g, by Umeyama's closed form (fixed-size: Eigen::umeyama's
  // dynamic matrices gain nothing for 3×3 and warn under AVX-512).
  Eigen::Vector3d mean_from = Eigen::Vector3d::Zero(), mean_to = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    mean_from += from[i] / n;
    mean_to += to[i] / n;
  }
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  double variance_from = 0;
  for (int i = 0; i < n; ++i) {
    covariance += (to[i] - mean_to) * (from[i] - mean_from).transpose() / n;
    variance_from += (from[i] - mean_from).squaredNorm() / n;
  }
  if (!(variance_from > 0)) throw ArgumentError("pose error: the estimated cameras share one centre");
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Vector3d sign(1, 1, 1);
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0) sign[2] = -1;  // a rotation, not a reflection
  const Eigen::Matrix3d G = svd.matrixU() * sign.asDiagonal() * svd.matrixV().transpose();
  const double scale = svd.singularValues().dot(sign) / variance_from;
  const Eigen::Vector3d g = mean_to - scale * G * mean_from;

  PoseError e;
  e.scale = scale;
  for (int i = 0; i < n; ++i) {
    // x_cam = R_est·(x_est − c) and x_est = Gᵀ·(x_truth − g)/s: in the truth's frame the
    // estimated camera's rotation is R_est·Gᵀ.
    const Eigen::Matrix3d relative =
        to_eigen(estimated[i].camera_from_world_rotation) * G.transpose() *
        to_eigen(truth[i].camera_from_world_rotation).transpose();
    // ‖R − I‖ = 2√2·sin(θ/2) for a rotation by θ: unlike the trace's arccos, exact near θ = 0
    // for rotations stored in float.
    const double half_sine = std::min(1.0, (relative - Eigen::Matrix3d::Identity()).norm() / (2.0 * std::sqrt(2.0)));
    const double rotation_deg = 2.0 * std::asin(half_sine) * 180.0 / 3.14159265358979323846;
    const double translation = (scale * G * from[i] + g - to[i]).norm();
    e.mean_rotation_deg += rotation_deg / n;
    e.max_rotation_deg = std::max(e.max_rotation_deg, rotation_deg);
    e.mean_translation += translation / n;
    e.max_translation = std::max(e.max_translation, translation);
  }
  return e;
}

}  // namespace splat
