#pragma once
// Real spherical harmonics up to degree 3, in the basis and sign convention of the
// reference 3DGS rasterizer (so models trained there keep their colours here).
// Templated on the scalar so gradient tests can run in double.
#include <glm/glm.hpp>

namespace splat {

constexpr double kShC0 = 0.28209479177387814;
constexpr double kShC1 = 0.4886025119029199;
constexpr double kShC2[5] = {1.0925484305920792, -1.0925484305920792, 0.31539156525252005,
                             -1.0925484305920792, 0.5462742152960396};
constexpr double kShC3[7] = {-0.5900435899266435, 2.890611442640554, -0.4570457994644658,
                             0.3731763325901154,  -0.4570457994644658, 1.445305721320277,
                             -0.5900435899266435};

// The (degree+1)^2 basis values for the unit direction `dir` (x, y, z), in coefficient order.
template <class T>
inline void sh_basis(int degree, const glm::vec<3, T>& dir, T* basis) {
  basis[0] = T(kShC0);
  if (degree < 1) return;
  const T x = dir.x, y = dir.y, z = dir.z;
  basis[1] = -T(kShC1) * y;
  basis[2] = T(kShC1) * z;
  basis[3] = -T(kShC1) * x;
  if (degree < 2) return;
  const T xx = x * x, yy = y * y, zz = z * z, xy = x * y, yz = y * z, xz = x * z;
  basis[4] = T(kShC2[0]) * xy;
  basis[5] = T(kShC2[1]) * yz;
  basis[6] = T(kShC2[2]) * (T(2) * zz - xx - yy);
  basis[7] = T(kShC2[3]) * xz;
  basis[8] = T(kShC2[4]) * (xx - yy);
  if (degree < 3) return;
  basis[9] = T(kShC3[0]) * y * (T(3) * xx - yy);
  basis[10] = T(kShC3[1]) * xy * z;
  basis[11] = T(kShC3[2]) * y * (T(4) * zz - xx - yy);
  basis[12] = T(kShC3[3]) * z * (T(2) * zz - T(3) * xx - T(3) * yy);
  basis[13] = T(kShC3[4]) * x * (T(4) * zz - xx - yy);
  basis[14] = T(kShC3[5]) * z * (xx - yy);
  basis[15] = T(kShC3[6]) * x * (xx - T(3) * yy);
}

// Σₖ coeffs[k] · Yₖ(dir) per channel; `coeffs` is [K, 3] with K >= (degree+1)^2.
// This is the raw SH value: the rasterizer adds 0.5 and clamps at 0.
template <class T>
inline glm::vec<3, T> sh_evaluate(int degree, const T* coeffs, const glm::vec<3, T>& dir) {
  T basis[16];
  sh_basis(degree, dir, basis);
  glm::vec<3, T> sum(T(0));
  const int count = (degree + 1) * (degree + 1);
  for (int k = 0; k < count; ++k)
    sum += basis[k] * glm::vec<3, T>(coeffs[3 * k], coeffs[3 * k + 1], coeffs[3 * k + 2]);
  return sum;
}

}  // namespace splat
