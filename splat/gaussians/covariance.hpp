#pragma once
// A Gaussian's shape: the rotation of its quaternion and its world-space covariance
// Σ = R S Sᵀ Rᵀ, each with its VJP, templated on the scalar so tests can check them in double.
// The projection (raster/projection_math.hpp) and density control (splitting along the
// axes) both build on these. Quaternions are (w, x, y, z) and need not be normalised.
#include <cmath>
#include <glm/glm.hpp>

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

// Matrix element by (row, column), as written on paper (glm indexes [column][row]).
template <class T>
inline T& at(Mat3<T>& m, int row, int col) { return m[col][row]; }
template <class T>
inline T at(const Mat3<T>& m, int row, int col) { return m[col][row]; }

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

// v_q from v_R. R is written in the normalised n = q/|q|; each entry's partial derivatives
// in (w, x, y, z) are listed beside it. Then n = q/|q| gives v_q = (v_n − n (n·v_n)) / |q|.
template <class T>
inline Vec4<T> quat_to_rotmat_vjp(const Vec4<T>& q, const Mat3<T>& v_r) {
  const T norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  const Vec4<T> n = q / norm;
  const T w = n[0], x = n[1], y = n[2], z = n[3];
  auto g = [&](int row, int col) { return at(v_r, row, col); };
  Vec4<T> v_n;
  // R00 = 1−2(y²+z²)   R01 = 2(xy−wz)   R02 = 2(xz+wy)
  // R10 = 2(xy+wz)     R11 = 1−2(x²+z²) R12 = 2(yz−wx)
  // R20 = 2(xz−wy)     R21 = 2(yz+wx)   R22 = 1−2(x²+y²)
  v_n[0] = T(2) * (-z * g(0, 1) + y * g(0, 2) + z * g(1, 0) - x * g(1, 2) - y * g(2, 0) + x * g(2, 1));
  v_n[1] = T(2) * (y * g(0, 1) + z * g(0, 2) + y * g(1, 0) - T(2) * x * g(1, 1) - w * g(1, 2) +
                   z * g(2, 0) + w * g(2, 1) - T(2) * x * g(2, 2));
  v_n[2] = T(2) * (-T(2) * y * g(0, 0) + x * g(0, 1) + w * g(0, 2) + x * g(1, 0) + z * g(1, 2) -
                   w * g(2, 0) + z * g(2, 1) - T(2) * y * g(2, 2));
  v_n[3] = T(2) * (-T(2) * z * g(0, 0) - w * g(0, 1) + x * g(0, 2) + w * g(1, 0) -
                   T(2) * z * g(1, 1) + y * g(1, 2) + x * g(2, 0) + y * g(2, 1));
  return (v_n - n * glm::dot(n, v_n)) / norm;
}

// World-space covariance Σ = R S Sᵀ Rᵀ with S = diag(scale).
template <class T>
inline Mat3<T> covariance_3d(const Vec3<T>& scale, const Mat3<T>& rotation) {
  Mat3<T> m = rotation;  // M = R S: column j of R scaled by scale[j]
  for (int j = 0; j < 3; ++j) m[j] *= scale[j];
  return m * glm::transpose(m);
}

// Σ = M Mᵀ with M = R S: v_M = (v_Σ + v_Σᵀ) M; column j of M is s_j R[:, j], so
// v_R[:, j] = s_j v_M[:, j] and v_s_j = R[:, j] · v_M[:, j].
template <class T>
inline void covariance_3d_vjp(const Vec3<T>& scale, const Mat3<T>& rotation, const Mat3<T>& v_cov,
                              Vec3<T>& v_scale, Mat3<T>& v_rotation) {
  Mat3<T> m = rotation;
  for (int j = 0; j < 3; ++j) m[j] *= scale[j];
  const Mat3<T> v_m = (v_cov + glm::transpose(v_cov)) * m;
  for (int j = 0; j < 3; ++j) {  // glm column j
    v_rotation[j] = v_m[j] * scale[j];
    v_scale[j] = glm::dot(rotation[j], v_m[j]);
  }
}

}  // namespace splat
