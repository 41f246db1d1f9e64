#pragma once
// One view's gradient of the SH coefficients, kept as the two factors it is made of.
//
// A Gaussian's colour in a view is max(Σₖ bₖ(d) cₖ + ½, 0), with d its unit view direction
// and bₖ the SH basis, so ∂L/∂c[k][ch] = bₖ(d) · g[ch], g = ∂L/∂colour (zero in a clamped
// channel): a rank-one row of 48 floats (degree 3) made of 6. The projection's backward
// writes these 6 instead of the 48 and Adam forms the row as it steps (adam.hpp): on a late
// lego400 iteration writing the 48 cost the projection's backward 1.7 of its 8 ms, and Adam
// read them once more. A batch of several views sums rank-one rows, which is not one, so
// batches keep the full rows (RasterGradients::sh_as_factors).
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "splat/core/simd.hpp"

namespace splat {

// The SH gradient rows of kLanes Gaussians, one per lane, from their factors: element
// (k, ch) of lane l's row is basis[k][l] · color_grad[ch][l] where `live` holds lane l, and
// zero where it does not (its basis may be NaN: a Gaussian at the camera centre), as are the
// bands above `degree` up to `width` floats. Writes the lanes set in `lanes` to rows[l]. The
// one place both the projection's backward (full rows) and ShGradientFactors::expand form
// them, so the two give the same rows to the bit.
void store_sh_gradient_rows(int degree, const simd::f32v basis[16], const simd::f32v color_grad[3],
                            simd::i32v live, std::uint32_t lanes, int width, float* const rows[simd::kLanes]);

struct ShGradientFactors {
  int degree = 0;  // the view's active SH degree: rows are zero above it
  std::array<std::vector<float>, 3> direction;   // [N] each: d's x, y, z
  std::array<std::vector<float>, 3> color_grad;  // [N] each: g's r, g, b

  std::size_t size() const { return direction[0].size(); }
  void resize(std::size_t n);
  // Rows first .. first + count − 1 of the gradient, written row-major to `rows`
  // ([count][width], width = the model's SH floats per Gaussian, ≥ 3 (degree + 1)²), for
  // count ≤ simd::kLanes. The basis is the projection backward's own lane computation
  // (sh_basis_xyz on kLanes directions) and each element the same single product, so the
  // rows are the ones it would have written, to the bit.
  void expand(std::size_t first, int count, int width, float* rows) const;
  // Zeroes rows first .. first + count − 1 (Gaussians without a gradient in this view).
  void clear(std::size_t first, std::size_t count);
};

}  // namespace splat
