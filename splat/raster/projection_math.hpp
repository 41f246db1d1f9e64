#pragma once
// Per-Gaussian projection math, templated on the scalar so tests can check it in double.
// Conventions: quaternions (w, x, y, z); camera axes x right, y down, z forward; 2D
// positions in the reference rasterizer's pixel convention, where the centre of pixel i
// is at coordinate i (hence the −0.5 against our camera's pixel-edge convention).
#include <cmath>
#include <glm/glm.hpp>

#include "splat/raster/raster_constants.hpp"

namespace splat {

template <class T> using Vec2 = glm::vec<2, T>;
template <class T> using Vec3 = glm::vec<3, T>;
template <class T> using Vec4 = glm::vec<4, T>;
template <class T> using Mat3 = glm::mat<3, 3, T>;

// glm stores matrices by column; this takes them by row, as written on paper.
template <class T>
inline Mat3<T> mat3_from_rows(T a00, T a01, T a02, T a10, T a11, T a12, T a20, T a21, T a22) {
  return Mat3<T>(a00, a10, a20, a01, a11, a21, a02, a12, a22);
}

// Rotation matrix of the normalised quaternion q = (w, x, y, z).
template <class T>
inline Mat3<T> quat_to_rotmat(const Vec4<T>& q) {
  const T inv_norm = T(1) / std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  const T w = q[0] * inv_norm, x = q[1] * inv_norm, y = q[2] * inv_norm, z = q[3] * inv_norm;
  return mat3_from_rows<T>(T(1) - T(2) * (y * y + z * z), T(2) * (x * y - w * z),
                           T(2) * (x * z + w * y),  //
                           T(2) * (x * y + w * z), T(1) - T(2) * (x * x + z * z),
                           T(2) * (y * z - w * x),  //
                           T(2) * (x * z - w * y), T(2) * (y * z + w * x),
                           T(1) - T(2) * (x * x + y * y));
}

// World-space covariance Σ = R S Sᵀ Rᵀ with S = diag(scale).
template <class T>
inline Mat3<T> covariance_3d(const Vec3<T>& scale, const Mat3<T>& rotation) {
  Mat3<T> m = rotation;  // M = R S: column j of R scaled by scale[j]
  for (int j = 0; j < 3; ++j) m[j] *= scale[j];
  return m * glm::transpose(m);
}

// Upper triangle of a symmetric 2x2 matrix [[xx, xy], [xy, yy]].
template <class T>
struct Sym2 {
  T xx, xy, yy;
};

// Screen-space covariance Σ' = J W Σ Wᵀ Jᵀ (+ dilation on the diagonal), where W is the
// camera-from-world rotation and J the Jacobian of the perspective projection at the
// Gaussian's camera-space mean, evaluated with x/z and y/z clamped to ±1.3·tan(fov/2) so
// Gaussians far outside the view do not blow up.
template <class T>
inline Sym2<T> covariance_2d(const Vec3<T>& mean_camera, const Mat3<T>& covariance_world,
                             const Mat3<T>& camera_from_world_rotation, T fx, T fy,
                             T tan_half_fov_x, T tan_half_fov_y) {
  const T z = mean_camera.z;
  const T limit_x = T(kJacobianClamp) * tan_half_fov_x;
  const T limit_y = T(kJacobianClamp) * tan_half_fov_y;
  const T x = std::min(limit_x, std::max(-limit_x, mean_camera.x / z)) * z;
  const T y = std::min(limit_y, std::max(-limit_y, mean_camera.y / z)) * z;
  const Mat3<T> jacobian = mat3_from_rows<T>(fx / z, T(0), -fx * x / (z * z),  //
                                             T(0), fy / z, -fy * y / (z * z),  //
                                             T(0), T(0), T(0));
  const Mat3<T> t = jacobian * camera_from_world_rotation;
  const Mat3<T> cov = t * covariance_world * glm::transpose(t);
  // glm indexes [column][row]; the matrix is symmetric up to rounding.
  return {cov[0][0] + T(kCovarianceDilation), cov[1][0], cov[1][1] + T(kCovarianceDilation)};
}

// Pixel position of a camera-space point, in the reference convention (pixel centres at
// integer coordinates): u = fx·x/z + cx − 0.5.
template <class T>
inline Vec2<T> project_to_pixel(const Vec3<T>& mean_camera, T fx, T fy, T cx, T cy) {
  const T inv_z = T(1) / mean_camera.z;
  return {fx * mean_camera.x * inv_z + cx - T(0.5), fy * mean_camera.y * inv_z + cy - T(0.5)};
}

// Conic (inverse of Σ') as (a, b, c) for [[a, b], [b, c]]; false when Σ' is singular.
template <class T>
inline bool invert_covariance_2d(const Sym2<T>& cov, Vec3<T>& conic) {
  const T det = cov.xx * cov.yy - cov.xy * cov.xy;
  if (det == T(0)) return false;
  const T inv_det = T(1) / det;
  conic = Vec3<T>(cov.yy * inv_det, -cov.xy * inv_det, cov.xx * inv_det);
  return true;
}

// Screen radius in pixels: ceil(3·sqrt(λmax)) of Σ', with the reference's floor on the
// eigenvalue gap.
template <class T>
inline int screen_radius(const Sym2<T>& cov) {
  const T det = cov.xx * cov.yy - cov.xy * cov.xy;
  const T mid = T(0.5) * (cov.xx + cov.yy);
  const T lambda_max = mid + std::sqrt(std::max(T(kMinEigenGap), mid * mid - det));
  return int(std::ceil(T(kRadiusSigmas) * std::sqrt(lambda_max)));
}

}  // namespace splat
