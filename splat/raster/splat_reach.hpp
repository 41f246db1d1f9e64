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

  // May a pixel centre at row offset dy = mean_y − y with dx = mean_x − x in [dx_lo, dx_hi] draw?
  bool row_segment(float dy, float dx_lo, float dx_hi) const {
    if (never_cull_) return true;
    return !(row_min(dy, dx_lo, dx_hi) > limit(far_size(dx_lo, dx_hi, dy)));  // NaN: draw
  }

 private:
  // min of q over dx ∈ [dx_lo, dx_hi] at fixed dy: at dx = −b dy / a, clamped.
  float row_min(float dy, float dx_lo, float dx_hi) const {
    const float centre = -b_over_a_ * dy;
    const float dx = std::clamp(centre, dx_lo, dx_hi) - centre;
    return s_.conic_a * dx * dx + det_over_a_ * dy * dy;
  }
  // The size of q's terms at the segment's farther end: the scale of the blend's rounding.
  float far_size(float dx_lo, float dx_hi, float dy) const {
    const float dx = std::max(std::abs(dx_lo), std::abs(dx_hi));
    dy = std::abs(dy);
    return s_.conic_a * dx * dx + 2.0f * std::abs(s_.conic_b) * dx * dy + s_.conic_c * dy * dy;
  }
  float limit(float size) const { return q_limit_ + 1e-5f * size; }

  const Splat2D& s_;
  float b_over_a_, det_over_a_;
  float q_limit_;
  bool never_cull_;
};

}  // namespace splat
