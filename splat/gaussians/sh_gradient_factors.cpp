#include "splat/gaussians/sh_gradient_factors.hpp"

#include <algorithm>
#include <cstring>

#include "splat/core/simd.hpp"
#include "splat/core/spherical_harmonics.hpp"
#include "splat/gaussians/gaussian_model.hpp"

namespace splat {

void ShGradientFactors::resize(std::size_t n) {
  for (int k = 0; k < 3; ++k) {
    direction[k].resize(n);
    color_grad[k].resize(n);
  }
}

void ShGradientFactors::clear(std::size_t first, std::size_t count) {
  for (int k = 0; k < 3; ++k) {
    std::fill_n(direction[k].begin() + std::ptrdiff_t(first), count, 0.0f);
    std::fill_n(color_grad[k].begin() + std::ptrdiff_t(first), count, 0.0f);
  }
}

void store_sh_gradient_rows(int degree, const simd::f32v basis[16], const simd::f32v color_grad[3],
                            simd::i32v live, std::uint32_t lanes, int width, float* const rows[simd::kLanes]) {
  using simd::f32v;
  const int coefficients = sh_coefficient_count(degree);
  f32v columns[kMaxShFloats];
  for (int k = 0; k < coefficients; ++k)
    for (int c = 0; c < 3; ++c) columns[3 * k + c] = live ? basis[k] * color_grad[c] : f32v{};
  simd::store_columns(columns, 3 * coefficients, lanes, rows);
  if (3 * coefficients < width)  // bands above the active degree
    for (std::uint32_t todo = lanes; todo != 0; todo &= todo - 1) {
      float* row = rows[__builtin_ctz(todo)];
      std::fill(row + 3 * coefficients, row + width, 0.0f);
    }
}

void ShGradientFactors::expand(std::size_t first, int count, int width, float* rows) const {
  using simd::f32v;
  // The factors of kLanes rows, one row per lane (lanes past `count` zero).
  f32v d[3] = {}, g[3] = {};
  for (int k = 0; k < 3; ++k) {
    std::memcpy(&d[k], &direction[k][first], std::size_t(count) * sizeof(float));
    std::memcpy(&g[k], &color_grad[k][first], std::size_t(count) * sizeof(float));
  }
  f32v basis[16];
  sh_basis_xyz(degree, d[0], d[1], d[2], basis);
  float* row[simd::kLanes];
  for (int l = 0; l < simd::kLanes; ++l) row[l] = rows + std::size_t(std::min(l, count - 1)) * std::size_t(width);
  // Every lane live: a lane without a gradient has zero factors, whose row is zero already.
  store_sh_gradient_rows(degree, basis, g, simd::i32v{} - 1, (1u << count) - 1, width, row);
}

}  // namespace splat
