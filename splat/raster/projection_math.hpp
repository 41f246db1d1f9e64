#pragma once
// Per-Gaussian projection math, templated on the scalar so tests can check it in double.
// Conventions: quaternions (w, x, y, z); camera axes x right, y down, z forward; 2D
// positions in the reference rasterizer's pixel convention, where the centre of pixel i
// is at coordinate i (hence the −0.5 against our camera's pixel-edge convention).
#include <cmath>
#include <glm/glm.hpp>

#include "splat/gaussians/covariance.hpp"
#include "splat/raster/raster_constants.hpp"

namespace splat {

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
inline Mat3<T> projection_jacobian(const Vec3<T>& mean_camera, T fx, T fy, T tan_half_fov_x,
                                   T tan_half_fov_y, T& x, T& y);

template <class T>
inline Sym2<T> covariance_2d(const Vec3<T>& mean_camera, const Mat3<T>& covariance_world,
                             const Mat3<T>& camera_from_world_rotation, T fx, T fy,
                             T tan_half_fov_x, T tan_half_fov_y) {
  T x, y;
  const Mat3<T> jacobian =
      projection_jacobian(mean_camera, fx, fy, tan_half_fov_x, tan_half_fov_y, x, y);
  const Mat3<T> t = jacobian * camera_from_world_rotation;
  const Mat3<T> cov = t * covariance_world * glm::transpose(t);
  return {at(cov, 0, 0) + T(kCovarianceDilation), at(cov, 0, 1),
          at(cov, 1, 1) + T(kCovarianceDilation)};
}

// The Jacobian of the perspective projection at `mean_camera`, x/z and y/z clamped.
// Returns it with the clamped x, y it was evaluated at.
template <class T>
inline Mat3<T> projection_jacobian(const Vec3<T>& mean_camera, T fx, T fy, T tan_half_fov_x,
                                   T tan_half_fov_y, T& x, T& y) {
  const T z = mean_camera.z;
  const T limit_x = T(kJacobianClamp) * tan_half_fov_x;
  const T limit_y = T(kJacobianClamp) * tan_half_fov_y;
  x = std::min(limit_x, std::max(-limit_x, mean_camera.x / z)) * z;
  y = std::min(limit_y, std::max(-limit_y, mean_camera.y / z)) * z;
  return mat3_from_rows<T>(fx / z, T(0), -fx * x / (z * z),  //
                           T(0), fy / z, -fy * y / (z * z),  //
                           T(0), T(0), T(0));
}

// Backward of covariance_2d: v_mean_camera (through the Jacobian) and v_covariance_world.
// The output is (Σ'00, Σ'01, Σ'11), so v_cov2d is a matrix G with G00 = v.xx, G01 = v.xy,
// G11 = v.yy (G10 = 0). With T = J W and Σ' = T Σ Tᵀ: v_Σ = Tᵀ G T, v_T = (G + Gᵀ) T Σ,
// v_J = v_T Wᵀ. Where x/z is clamped, x = ±limit·z: the gradient to the camera x is zero
// and z receives ±limit times the x cotangent instead (the exact derivative of the clamp).
template <class T>
inline void covariance_2d_vjp(const Vec3<T>& mean_camera, const Mat3<T>& covariance_world,
                              const Mat3<T>& camera_from_world_rotation, T fx, T fy,
                              T tan_half_fov_x, T tan_half_fov_y, const Sym2<T>& v_cov2d,
                              Vec3<T>& v_mean_camera, Mat3<T>& v_covariance_world,
                              Mat3<T>* v_camera_from_world_rotation = nullptr) {
  T x, y;
  const Mat3<T> jacobian =
      projection_jacobian(mean_camera, fx, fy, tan_half_fov_x, tan_half_fov_y, x, y);
  const Mat3<T> t = jacobian * camera_from_world_rotation;
  Mat3<T> g(T(0));
  at(g, 0, 0) = v_cov2d.xx;
  at(g, 0, 1) = v_cov2d.xy;
  at(g, 1, 1) = v_cov2d.yy;
  v_covariance_world = glm::transpose(t) * g * t;
  const Mat3<T> v_t = (g + glm::transpose(g)) * t * covariance_world;
  // W's direct use in T = J W (its use in the camera-space mean is camera_pose_vjp's).
  if (v_camera_from_world_rotation) *v_camera_from_world_rotation = glm::transpose(jacobian) * v_t;
  const Mat3<T> v_j = v_t * glm::transpose(camera_from_world_rotation);
  const T z = mean_camera.z, z2 = z * z, z3 = z2 * z;
  // J00 = fx/z, J02 = −fx x/z², J11 = fy/z, J12 = −fy y/z².
  const T v_x = -fx / z2 * at(v_j, 0, 2);
  const T v_y = -fy / z2 * at(v_j, 1, 2);
  T v_z = -fx / z2 * at(v_j, 0, 0) + T(2) * fx * x / z3 * at(v_j, 0, 2) - fy / z2 * at(v_j, 1, 1) +
          T(2) * fy * y / z3 * at(v_j, 1, 2);
  const T limit_x = T(kJacobianClamp) * tan_half_fov_x;
  const T limit_y = T(kJacobianClamp) * tan_half_fov_y;
  const T ratio_x = mean_camera.x / z, ratio_y = mean_camera.y / z;
  T v_mx = 0, v_my = 0;
  if (ratio_x < -limit_x || ratio_x > limit_x) v_z += (x / z) * v_x; else v_mx = v_x;
  if (ratio_y < -limit_y || ratio_y > limit_y) v_z += (y / z) * v_y; else v_my = v_y;
  v_mean_camera = Vec3<T>(v_mx, v_my, v_z);
}

// ---- The camera's pose ------------------------------------------------------------------
// A view's pose is its camera-from-world rotation W and translation t. A Gaussian reaches
// them through its camera-space mean m_c = W m + t (which the pixel position and the
// Jacobian read), through W in Σ' = J W Σ Wᵀ Jᵀ (covariance_2d_vjp's optional output) and
// through the camera centre C = −Wᵀ t, from which its SH colour is seen (direction m − C).
// Given ∂L/∂m_c and ∂L/∂C, this adds the first and the last to v_rotation and v_translation:
//   m_c = W m + t:  v_W += v_m_c mᵀ,  v_t += v_m_c
//   C = −Wᵀ t:      v_W += −t v_Cᵀ,   v_t += −W v_C
template <class T>
inline void camera_pose_vjp(const Vec3<T>& mean_world, const Mat3<T>& camera_from_world_rotation,
                            const Vec3<T>& camera_from_world_translation, const Vec3<T>& v_mean_camera,
                            const Vec3<T>& v_camera_center, Mat3<T>& v_rotation, Vec3<T>& v_translation) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      at(v_rotation, r, c) += v_mean_camera[r] * mean_world[c] - camera_from_world_translation[r] * v_camera_center[c];
  v_translation += v_mean_camera - camera_from_world_rotation * v_camera_center;
}

// A correction of a view's pose, applied in the camera's frame about a pivot p (a fixed
// camera-space point): W = R(q) W₀, t = R(q)(t₀ − p) + p + τ, with R(q) the rotation of the
// quaternion q (normalised inside, as a Gaussian's) and τ a translation; q = (1, 0, 0, 0),
// τ = 0 leave the pose as it is. With p at the depth of the scene, q orbits the camera about
// it and τ pans: the image's shift (strongly constrained) and its parallax (weakly) become
// separate coordinates, which Adam's per-coordinate steps need to move both at one pace.
template <class T>
inline void apply_pose_correction(const Vec4<T>& q, const Vec3<T>& tau, const Mat3<T>& rotation0,
                                  const Vec3<T>& translation0, Mat3<T>& rotation, Vec3<T>& translation,
                                  const Vec3<T>& pivot = Vec3<T>(0)) {
  const Mat3<T> r = quat_to_rotmat(q);
  rotation = r * rotation0;
  translation = r * (translation0 - pivot) + pivot + tau;
}

// Its backward: v_R = v_W W₀ᵀ + v_t (t₀ − p)ᵀ, then through the quaternion; v_τ = v_t.
template <class T>
inline void apply_pose_correction_vjp(const Vec4<T>& q, const Mat3<T>& rotation0, const Vec3<T>& translation0,
                                      const Mat3<T>& v_rotation, const Vec3<T>& v_translation, Vec4<T>& v_q,
                                      Vec3<T>& v_tau, const Vec3<T>& pivot = Vec3<T>(0)) {
  Mat3<T> v_r = v_rotation * glm::transpose(rotation0);
  const Vec3<T> arm = translation0 - pivot;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) at(v_r, r, c) += v_translation[r] * arm[c];
  v_q = quat_to_rotmat_vjp(q, v_r);
  v_tau = v_translation;
}

// Pixel position of a camera-space point, in the reference convention (pixel centres at
// integer coordinates): u = fx·x/z + cx − 0.5.
template <class T>
inline Vec2<T> project_to_pixel(const Vec3<T>& mean_camera, T fx, T fy, T cx, T cy) {
  const T inv_z = T(1) / mean_camera.z;
  return {fx * mean_camera.x * inv_z + cx - T(0.5), fy * mean_camera.y * inv_z + cy - T(0.5)};
}

template <class T>
inline Vec3<T> project_to_pixel_vjp(const Vec3<T>& mean_camera, T fx, T fy, const Vec2<T>& v_pixel) {
  const T inv_z = T(1) / mean_camera.z;
  return {fx * inv_z * v_pixel.x, fy * inv_z * v_pixel.y,
          -(fx * mean_camera.x * v_pixel.x + fy * mean_camera.y * v_pixel.y) * inv_z * inv_z};
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

// Backward of invert_covariance_2d. With Q = Σ'⁻¹, dQ = −Q dΣ' Q. The conic's b stands for
// both off-diagonal entries of Q, so its cotangent is split over them (H01 = H10 = v_b/2);
// Σ'01 is likewise one number standing for both entries of Σ', so v_xy sums both.
template <class T>
inline Sym2<T> invert_covariance_2d_vjp(const Vec3<T>& conic, const Vec3<T>& v_conic) {
  const T a = conic.x, b = conic.y, c = conic.z;
  const T h00 = v_conic.x, h01 = T(0.5) * v_conic.y, h11 = v_conic.z;
  // Q H Q for symmetric Q = [[a, b], [b, c]] and H = [[h00, h01], [h01, h11]].
  const T qh00 = a * h00 + b * h01, qh01 = a * h01 + b * h11;
  const T qh10 = b * h00 + c * h01, qh11 = b * h01 + c * h11;
  const T m00 = qh00 * a + qh01 * b, m01 = qh00 * b + qh01 * c, m11 = qh10 * b + qh11 * c;
  return {-m00, T(-2) * m01, -m11};
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
