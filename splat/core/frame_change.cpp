#include "splat/core/frame_change.hpp"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <string>

#include "splat/core/error.hpp"

namespace splat {

namespace {

Eigen::Matrix3d to_eigen(const glm::dmat3& m) {
  Eigen::Matrix3d e;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) e(r, c) = m[c][r];  // glm is column-major: m[column][row]
  return e;
}

glm::dmat3 to_glm(const Eigen::Matrix3d& e) {
  glm::dmat3 m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m[c][r] = e(r, c);
  return m;
}

glm::dvec3 centre(const Camera& camera) { return glm::dvec3(camera.center_in_world()); }

std::vector<glm::dvec3> centres(const std::vector<Camera>& cameras) {
  std::vector<glm::dvec3> out;
  for (const Camera& camera : cameras) out.push_back(centre(camera));
  return out;
}

glm::dvec3 mean_of(const std::vector<glm::dvec3>& points) {
  glm::dvec3 mean(0.0);
  for (const glm::dvec3& p : points) mean += p / double(points.size());
  return mean;
}

// The rotation nearest to `m` (by its SVD; a rotation, not a reflection), and the diagonal
// that makes it one: the closed form both fits share.
glm::dmat3 nearest_rotation(const Eigen::Matrix3d& m, Eigen::Vector3d* singular_values_signed = nullptr) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Vector3d sign(1, 1, 1);
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0) sign[2] = -1;
  if (singular_values_signed) *singular_values_signed = svd.singularValues().cwiseProduct(sign);
  return to_glm(svd.matrixU() * sign.asDiagonal() * svd.matrixV().transpose());
}

}  // namespace

FrameChange FrameChange::inverse() const {
  // x_old = Qᵀ·(x_new − d)/s.
  FrameChange undo;
  undo.scale = 1.0 / scale;
  undo.rotation = glm::transpose(rotation);
  undo.translation = -(undo.rotation * translation) / scale;
  return undo;
}

Camera FrameChange::applied_to(const Camera& camera) const {
  // x_cam = R·(x_old − c) and x_old = Qᵀ·(x_new − d)/s, so in the new frame the camera turns
  // by R·Qᵀ and stands at s·Q·c + d; the factor 1/s scales depth and offsets alike.
  const glm::dmat3 new_rotation = glm::dmat3(camera.camera_from_world_rotation) * glm::transpose(rotation);
  const glm::dvec3 new_centre = scale * (rotation * centre(camera)) + translation;
  Camera moved = camera;
  moved.camera_from_world_rotation = glm::mat3(new_rotation);
  moved.camera_from_world_translation = glm::vec3(-(new_rotation * new_centre));
  return moved;
}

FrameChange fit_frame_change(const std::vector<Camera>& recorded, const std::vector<Camera>& refined) {
  if (recorded.size() != refined.size())
    throw ArgumentError("frame change: " + std::to_string(recorded.size()) + " recorded cameras against " +
                        std::to_string(refined.size()) + " refined ones");
  if (recorded.empty()) throw ArgumentError("frame change: no cameras");
  const std::size_t n = recorded.size();

  // Each view alone says Q = R_refinedᵀ·R_recorded; the rotation nearest their sum (by SVD,
  // a rotation and not a reflection) is their chordal L2 mean.
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < n; ++i)
    sum += to_eigen(glm::transpose(glm::dmat3(refined[i].camera_from_world_rotation)) *
                    glm::dmat3(recorded[i].camera_from_world_rotation));
  FrameChange change;
  change.rotation = nearest_rotation(sum);

  const std::vector<glm::dvec3> from = centres(recorded), to = centres(refined);
  const glm::dvec3 mean_recorded = mean_of(from), mean_refined = mean_of(to);
  double along = 0, spread = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec3 turned = change.rotation * (from[i] - mean_recorded);
    along += glm::dot(turned, to[i] - mean_refined);
    spread += glm::dot(turned, turned);
  }
  // Coinciding centres (float centres agree to ~1e-7 of their size) carry no scale.
  if (spread > 1e-12 * double(n) * (1.0 + glm::dot(mean_recorded, mean_recorded)) && along > 0)
    change.scale = along / spread;
  change.translation = mean_refined - change.scale * (change.rotation * mean_recorded);
  return change;
}

FrameChange fit_point_similarity(const std::vector<glm::dvec3>& from, const std::vector<glm::dvec3>& to) {
  if (from.size() != to.size())
    throw ArgumentError("similarity fit: " + std::to_string(from.size()) + " points against " +
                        std::to_string(to.size()));
  const std::size_t n = from.size();
  if (n < 3) throw ArgumentError("similarity fit: needs at least 3 points");
  const glm::dvec3 mean_from = mean_of(from), mean_to = mean_of(to);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  double variance_from = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec3 a = from[i] - mean_from, b = to[i] - mean_to;
    covariance += Eigen::Vector3d(b.x, b.y, b.z) * Eigen::Vector3d(a.x, a.y, a.z).transpose() / double(n);
    variance_from += glm::dot(a, a) / double(n);
  }
  if (!(variance_from > 0)) throw ArgumentError("similarity fit: the points to fit share one position");
  FrameChange change;
  Eigen::Vector3d signed_singular_values;
  change.rotation = nearest_rotation(covariance, &signed_singular_values);
  change.scale = signed_singular_values.sum() / variance_from;
  change.translation = mean_to - change.scale * (change.rotation * mean_from);
  return change;
}

}  // namespace splat
