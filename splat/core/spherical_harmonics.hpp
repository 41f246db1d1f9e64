#pragma once
// Real spherical harmonics up to degree 3, in the basis and sign convention of the
// reference 3DGS rasterizer (so models trained there keep their colours here).
// Templated on the scalar so gradient tests can run in double.
#include <glm/glm.hpp>
#include <type_traits>

#include "splat/core/simd.hpp"

namespace splat {

constexpr double kShC0 = 0.28209479177387814;
constexpr double kShC1 = 0.4886025119029199;
constexpr double kShC2[5] = {1.0925484305920792, -1.0925484305920792, 0.31539156525252005,
                             -1.0925484305920792, 0.5462742152960396};
constexpr double kShC3[7] = {-0.5900435899266435, 2.890611442640554, -0.4570457994644658,
                             0.3731763325901154,  -0.4570457994644658, 1.445305721320277,
                             -0.5900435899266435};

// T(c) for a scalar T; c in every lane for a SIMD vector (simd::f32v), so the basis below
// also evaluates kLanes directions at once.
template <class T>
inline T sh_constant(double c) {
  if constexpr (std::is_arithmetic_v<T>) return T(c);
  else return simd::broadcast(float(c));
}

// The (degree+1)^2 basis values for the unit direction (x, y, z), in coefficient order.
template <class T>
inline void sh_basis_xyz(int degree, T x, T y, T z, T* basis) {
  auto k = [](double c) { return sh_constant<T>(c); };
  basis[0] = k(kShC0);
  if (degree < 1) return;
  basis[1] = -k(kShC1) * y;
  basis[2] = k(kShC1) * z;
  basis[3] = -k(kShC1) * x;
  if (degree < 2) return;
  const T xx = x * x, yy = y * y, zz = z * z, xy = x * y, yz = y * z, xz = x * z;
  basis[4] = k(kShC2[0]) * xy;
  basis[5] = k(kShC2[1]) * yz;
  basis[6] = k(kShC2[2]) * (k(2) * zz - xx - yy);
  basis[7] = k(kShC2[3]) * xz;
  basis[8] = k(kShC2[4]) * (xx - yy);
  if (degree < 3) return;
  basis[9] = k(kShC3[0]) * y * (k(3) * xx - yy);
  basis[10] = k(kShC3[1]) * xy * z;
  basis[11] = k(kShC3[2]) * y * (k(4) * zz - xx - yy);
  basis[12] = k(kShC3[3]) * z * (k(2) * zz - k(3) * xx - k(3) * yy);
  basis[13] = k(kShC3[4]) * x * (k(4) * zz - xx - yy);
  basis[14] = k(kShC3[5]) * z * (xx - yy);
  basis[15] = k(kShC3[6]) * x * (xx - k(3) * yy);
}

template <class T>
inline void sh_basis(int degree, const glm::vec<3, T>& dir, T* basis) {
  sh_basis_xyz(degree, dir.x, dir.y, dir.z, basis);
}

// Σₖ coeffs[k] · Yₖ(dir) per channel; `coeffs` is [K, 3] with K >= (degree+1)^2.
// This is the raw SH value: the rasterizer adds 0.5 and clamps at 0.
template <class T>
inline glm::vec<3, T> sh_evaluate(int degree, const T* coeffs, const glm::vec<3, T>& dir) {
  T basis[16];
  sh_basis(degree, dir, basis);
  // Channel by channel, in the order the projection's SIMD colour pass sums (the same
  // result, lane for lane).
  T sum[3] = {T(0), T(0), T(0)};
  const int count = (degree + 1) * (degree + 1);
  for (int k = 0; k < count; ++k)
    for (int c = 0; c < 3; ++c) sum[c] += basis[k] * coeffs[3 * k + c];
  return {sum[0], sum[1], sum[2]};
}

// Backward of sh_basis: (v_x, v_y, v_z) += Σₖ v_basis[k] ∂Yₖ/∂dir (dir treated as free, not
// unit; the caller chains through the normalisation). Each line differentiates the matching
// line of sh_basis_xyz. For a scalar T and for kLanes directions at once (simd::f32v).
template <class T>
inline void sh_basis_vjp_xyz(int degree, T x, T y, T z, const T* v_basis, T& v_x, T& v_y, T& v_z) {
  auto k = [](double c) { return sh_constant<T>(c); };
  if (degree < 1) return;
  v_y += -k(kShC1) * v_basis[1];
  v_z += k(kShC1) * v_basis[2];
  v_x += -k(kShC1) * v_basis[3];
  if (degree < 2) return;
  const T xx = x * x, yy = y * y, zz = z * z;
  // One term per basis function: its factor c·v_basis[k] times each partial derivative.
  auto add = [&](T factor, T dx, T dy, T dz) {
    v_x += factor * dx;
    v_y += factor * dy;
    v_z += factor * dz;
  };
  const T zero = k(0);
  add(k(kShC2[0]) * v_basis[4], y, x, zero);
  add(k(kShC2[1]) * v_basis[5], zero, z, y);
  add(k(kShC2[2]) * v_basis[6], k(-2) * x, k(-2) * y, k(4) * z);
  add(k(kShC2[3]) * v_basis[7], z, zero, x);
  add(k(kShC2[4]) * v_basis[8], k(2) * x, k(-2) * y, zero);
  if (degree < 3) return;
  add(k(kShC3[0]) * v_basis[9], k(6) * x * y, k(3) * xx - k(3) * yy, zero);
  add(k(kShC3[1]) * v_basis[10], y * z, x * z, x * y);
  add(k(kShC3[2]) * v_basis[11], k(-2) * x * y, k(4) * zz - xx - k(3) * yy, k(8) * y * z);
  add(k(kShC3[3]) * v_basis[12], k(-6) * x * z, k(-6) * y * z, k(6) * zz - k(3) * xx - k(3) * yy);
  add(k(kShC3[4]) * v_basis[13], k(4) * zz - k(3) * xx - yy, k(-2) * x * y, k(8) * x * z);
  add(k(kShC3[5]) * v_basis[14], k(2) * x * z, k(-2) * y * z, xx - yy);
  add(k(kShC3[6]) * v_basis[15], k(3) * xx - k(3) * yy, k(-6) * x * y, zero);
}

template <class T>
inline glm::vec<3, T> sh_basis_vjp(int degree, const glm::vec<3, T>& dir, const T* v_basis) {
  glm::vec<3, T> v(T(0));
  sh_basis_vjp_xyz(degree, dir.x, dir.y, dir.z, v_basis, v.x, v.y, v.z);
  return v;
}

// Backward of sh_evaluate: v_coeffs[k][c] += Yₖ v_out[c] (accumulated), and returns v_dir.
template <class T>
inline glm::vec<3, T> sh_evaluate_vjp(int degree, const T* coeffs, const glm::vec<3, T>& dir,
                                      const glm::vec<3, T>& v_out, T* v_coeffs) {
  T basis[16], v_basis[16] = {};  // zeroed: GCC cannot see that only [0, count) is read
  sh_basis(degree, dir, basis);
  const int count = (degree + 1) * (degree + 1);
  for (int k = 0; k < count; ++k) {
    v_basis[k] = T(0);
    for (int c = 0; c < 3; ++c) {
      v_coeffs[3 * k + c] += basis[k] * v_out[c];
      v_basis[k] += coeffs[3 * k + c] * v_out[c];
    }
  }
  return sh_basis_vjp(degree, dir, v_basis);
}

}  // namespace splat
