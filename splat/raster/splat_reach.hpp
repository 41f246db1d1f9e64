#pragma once
// Where a splat can draw at all. α = min(kMaxAlpha, o·exp(−q/2)) reaches kMinAlpha only where
// q = a dx² + 2b dx dy + c dy² ≤ q_max (Splat2D::q_max), with d = splat centre − pixel centre.
// The test lets the blend and its backward skip the chunks of a row that cannot draw.
//
// It is conservative, so that no image or gradient changes: the minimum of q over a row
// segment of pixel centres is taken in the continuous plane (a superset of the pixels), in a
// form without cancellation, a (dx + b dy / a)² + (det / a) dy², and compared with q_max plus
// a margin far above the rounding of the per-pixel arithmetic in the blend (whose error grows
// with the size of the terms a dx², b dx dy, c dy²).
#include <algorithm>
#include <cmath>

#include "splat/core/simd.hpp"
#include "splat/raster/project.hpp"

namespace splat {

class SplatReach {
 public:
  explicit SplatReach(const Splat2D& s)
      : s_(s),
        b_over_a_(s.conic_b / s.conic_a),
        det_over_a_((s.conic_a * s.conic_c - s.conic_b * s.conic_b) / s.conic_a),
        q_limit_(s.q_max * (1 + 1e-3f) + 1e-2f),
        never_cull_(!(s.conic_a > 0.0f)) {}  // degenerate: hand-made in tests

  // The lanes of `dy` (row offsets mean_y − y, one row per lane) in which some pixel centre
  // with dx = mean_x − x in [dx_lo, dx_hi] may draw.
  simd::i32v rows_may_draw(simd::f32v dy, float dx_lo, float dx_hi) const {
    using simd::f32v;
    if (never_cull_) return simd::i32v{} - 1;
    const f32v centre = -b_over_a_ * dy;
    const f32v dx = simd::min(simd::max(centre, simd::broadcast(dx_lo)), simd::broadcast(dx_hi)) - centre;
    const f32v q = s_.conic_a * dx * dx + det_over_a_ * dy * dy;
    const float dx_far = std::max(std::abs(dx_lo), std::abs(dx_hi));
    const f32v dy_far = simd::max(dy, -dy);
    const f32v size = s_.conic_a * dx_far * dx_far + (2.0f * std::abs(s_.conic_b) * dx_far) * dy_far +
                      s_.conic_c * dy * dy;
    return ~(q > q_limit_ + 1e-5f * size);  // NaN: draw
  }

 private:
  const Splat2D& s_;
  float b_over_a_, det_over_a_;
  float q_limit_;
  bool never_cull_;
};

}  // namespace splat
