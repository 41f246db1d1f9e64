#pragma once
// The projection of kLanes Gaussians at once, one per lane: projection_math.hpp's scalar
// functions (which the tests check in double and against finite differences) written out
// term for term for simd::f32v. The forward pass (project.cpp) and its backward
// (project_backward.cpp) both build on the shape computed here, so the backward recomputes
// exactly what the forward drew. tests/raster/project_lanes_test.cpp and
// tests/raster/project_backward_lanes_test.cpp hold every lane to the scalar functions.
#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>

#include "splat/core/camera.hpp"
#include "splat/core/simd.hpp"
#include "splat/gaussians/gaussian_model.hpp"
#include "splat/raster/raster_constants.hpp"

namespace splat::lanes {

using simd::f32v;
using simd::i32v;
using simd::kLanes;

// A 3 × 3 matrix per lane, [row][column].
struct LaneMat3 {
  f32v m[3][3];
};

// Row i, column j: a(i,0)·b(0,j) + a(i,1)·b(1,j) + a(i,2)·b(2,j), summed as glm does.
inline LaneMat3 multiply(const LaneMat3& a, const LaneMat3& b) {
  LaneMat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
  return r;
}

inline LaneMat3 transpose(const LaneMat3& a) {
  LaneMat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.m[i][j] = a.m[j][i];
  return r;
}

inline LaneMat3 broadcast(const glm::mat3& a) {  // glm is [column][row]
  LaneMat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.m[i][j] = simd::broadcast(a[j][i]);
  return r;
}

inline float exp_of(float x) { return std::exp(x); }
inline float log_of(float x) { return std::log(x); }

// std::min(a, b) and std::max(a, b) per lane, NaN handling included.
inline f32v min_of(f32v a, f32v b) { return b < a ? b : a; }
inline f32v max_of(f32v a, f32v b) { return a < b ? b : a; }
inline i32v min_of(i32v a, i32v b) { return b < a ? b : a; }
inline i32v max_of(i32v a, i32v b) { return a < b ? b : a; }

// The parameters of Gaussians first .. first + kLanes − 1, one per lane (the lanes past
// `lanes` repeat the last Gaussian).
struct LaneGaussians {
  f32v mean[3], log_scale[3], quat[4], opacity_logit;

  LaneGaussians(const GaussianModel& model, std::size_t first, int lanes) {
    for (int l = 0; l < kLanes; ++l) {
      const std::size_t i = first + std::size_t(std::min(l, lanes - 1));
      for (int k = 0; k < 3; ++k) mean[k][l] = model.means[3 * i + k];
      for (int k = 0; k < 3; ++k) log_scale[k][l] = model.log_scales[3 * i + k];
      for (int k = 0; k < 4; ++k) quat[k][l] = model.quats[4 * i + k];
      opacity_logit[l] = model.opacity_logits[i];
    }
  }
};

// quat_to_rotmat.
inline LaneMat3 rotation_of(const f32v q[4]) {
  const f32v inv_norm = 1.0f / simd::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  const f32v w = q[0] * inv_norm, x = q[1] * inv_norm, y = q[2] * inv_norm, z = q[3] * inv_norm;
  return {{{1.0f - 2.0f * (y * y + z * z), 2.0f * (x * y - w * z), 2.0f * (x * z + w * y)},
           {2.0f * (x * y + w * z), 1.0f - 2.0f * (x * x + z * z), 2.0f * (y * z - w * x)},
           {2.0f * (x * z - w * y), 2.0f * (y * z + w * x), 1.0f - 2.0f * (x * x + y * y)}}};
}

// covariance_3d: M = R S, Σ = M Mᵀ.
inline LaneMat3 covariance_of(const f32v scale[3], const LaneMat3& rotation) {
  LaneMat3 m = rotation;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m.m[i][j] = m.m[i][j] * scale[j];
  return multiply(m, transpose(m));
}

// What the projection needs of the camera, once per frame.
struct LaneView {
  LaneMat3 rotation;  // camera from world, W
  f32v translation[3];
  float fx, fy, limit_x, limit_y;  // limits: kJacobianClamp · tan(fov/2)

  explicit LaneView(const Camera& camera)
      : rotation(broadcast(camera.camera_from_world_rotation)),
        fx(camera.fx),
        fy(camera.fy),
        limit_x(kJacobianClamp * camera.tan_half_fov_x()),
        limit_y(kJacobianClamp * camera.tan_half_fov_y()) {
    for (int k = 0; k < 3; ++k) translation[k] = simd::broadcast(camera.camera_from_world_translation[k]);
  }
};

// A Gaussian's shape as one view sees it: Camera::camera_from_world, the 3D covariance and
// covariance_2d with projection_jacobian, kept whole because the backward pass reads its
// intermediates.
struct LaneShape {
  f32v mean_camera[3];
  f32v scale[3];          // exp(log-scale)
  LaneMat3 rotation;      // of the raw quaternion, normalised
  LaneMat3 cov3d;         // Σ
  f32v clamped_x, clamped_y;  // camera x, y with x/z, y/z clamped (projection_jacobian's x, y)
  LaneMat3 jacobian;      // J
  LaneMat3 jacobian_view;  // T = J W
  f32v xx, xy, yy;        // Σ' = T Σ Tᵀ, the diagonal dilated

  LaneShape(const LaneGaussians& g, const LaneView& view) {
    for (int i = 0; i < 3; ++i)
      mean_camera[i] = view.rotation.m[i][0] * g.mean[0] + view.rotation.m[i][1] * g.mean[1] +
                       view.rotation.m[i][2] * g.mean[2] + view.translation[i];
    for (int k = 0; k < 3; ++k) scale[k] = simd::per_lane(g.log_scale[k], exp_of);
    rotation = rotation_of(g.quat);
    cov3d = covariance_of(scale, rotation);
    const f32v z = mean_camera[2];
    clamped_x = min_of(simd::broadcast(view.limit_x), max_of(simd::broadcast(-view.limit_x), mean_camera[0] / z)) * z;
    clamped_y = min_of(simd::broadcast(view.limit_y), max_of(simd::broadcast(-view.limit_y), mean_camera[1] / z)) * z;
    const f32v zero{};
    jacobian = {{{view.fx / z, zero, -view.fx * clamped_x / (z * z)},
                 {zero, view.fy / z, -view.fy * clamped_y / (z * z)},
                 {zero, zero, zero}}};
    jacobian_view = multiply(jacobian, view.rotation);
    const LaneMat3 cov = multiply(multiply(jacobian_view, cov3d), transpose(jacobian_view));
    xx = cov.m[0][0] + kCovarianceDilation;
    xy = cov.m[0][1];
    yy = cov.m[1][1] + kCovarianceDilation;
  }
};

}  // namespace splat::lanes
