#pragma once
// Where a splat can draw at all. α = min(kMaxAlpha, o·exp(−q/2)) reaches kMinAlpha only where
// q = a dx² + 2b dx dy + c dy² ≤ q_max (Splat2D::q_max), with d = splat centre − pixel centre.
// The test lets the blend and its backward skip the chunks of a tile that cannot draw.
//
// For a chunk column (kLanes pixel centres of a row, dx in [dx_lo, dx_hi]) the rows that may
// draw are an interval: the ellipse q ≤ L cut to the strip dx_lo ≤ dx ≤ dx_hi is convex, so
// its dy form an interval. Its top is the ellipse's top point (dy = Y = √(L a / det), at
// dx = −(b/a) Y) where that lies in the strip, else where the nearer edge of the strip meets
// the ellipse; both are the larger root of q(x, dy) = L at x = clamp(−(b/a) Y, dx_lo, dx_hi),
// dy = (−b x + √(c L − det x²)) / c. The bottom is the mirror image. Eight splats at a time
// (one per lane): a handful of square roots and divisions per eight list entries, where a
// test of every row cost a division per entry and four vector tests per chunk column.
//
// It is conservative, so that no image or gradient changes: L is q_max plus a margin far above
// the rounding of the per-pixel arithmetic in the blend (whose error grows with the size of
// the terms a dx², b dx dy, c dy²), and then a little more, which covers this file's own
// rounding (the discriminant's absolute error is a few ulps of c·L, the margin adds 10⁻⁴ c L);
// the rows found are widened by a margin for the rounding of the roots. Degenerate conics
// (hand-made in tests, or NaN) walk their whole box.
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "splat/core/simd.hpp"
#include "splat/raster/project.hpp"
#include "splat/raster/raster_constants.hpp"

namespace splat {

// The fields of eight splats the reach needs, one splat per lane.
struct SplatLanes {
  simd::f32v mean_x, mean_y, conic_a, conic_b, conic_c, extent_x, extent_y, q_max;

  // splats[l] for l < count; the other lanes repeat splats[0] (their result is not used).
  // The record's first and last eight floats, each an 8 × 8 transpose: filled lane by lane,
  // a vector waits on a store-forwarding stall when it is read back.
  SplatLanes(const Splat2D* const splats[simd::kLanes], int count) {
    static_assert(sizeof(Splat2D) == 13 * sizeof(float) && offsetof(Splat2D, conic_c) == 4 * sizeof(float) &&
                      offsetof(Splat2D, extent_x) == 10 * sizeof(float),
                  "the head holds mean and conic, the tail extent and q_max");
    constexpr int kTail = 5;  // the tail: opacity, colour, depth, extent, q_max
    const float* head_rows[simd::kLanes];
    const float* tail_rows[simd::kLanes];
    for (int l = 0; l < simd::kLanes; ++l) {
      head_rows[l] = &(l < count ? splats[l] : splats[0])->mean_x;
      tail_rows[l] = head_rows[l] + kTail;
    }
    simd::f32v head[simd::kLanes], tail[simd::kLanes];
    simd::load_columns(head_rows, simd::kLanes, head);
    simd::load_columns(tail_rows, simd::kLanes, tail);
    mean_x = head[0], mean_y = head[1], conic_a = head[2], conic_b = head[3], conic_c = head[4];
    extent_x = tail[10 - kTail], extent_y = tail[11 - kTail], q_max = tail[12 - kTail];
  }
};

// Per lane, rows of a tile as absolute row coordinates in float: [first, last], empty when
// first > last.
struct RowSpan {
  simd::f32v first, last;
};

// Eight splats' reach in one tile: the terms every chunk column of the tile shares.
class ReachLanes {
 public:
  // The tile's pixel centres span x in [x0, x0 + kTileSize − 1], y likewise from y0.
  ReachLanes(const SplatLanes& s, float x0, float y0) : s_(s) {
    using simd::f32v;
    using simd::f64v;
    const f32v a = s.conic_a, b = s.conic_b, c = s.conic_c;
    // det in double: a·c and b² are exact there, so a thin ellipse's det (a c ≈ b²) keeps its bits.
    const f64v a64 = __builtin_convertvector(a, f64v), b64 = __builtin_convertvector(b, f64v),
               c64 = __builtin_convertvector(c, f64v);
    det_ = __builtin_convertvector(a64 * c64 - b64 * b64, f32v);
    // The blend's rounding margin at the tile's farthest pixel from the centre (the size of the
    // exponent's terms there bounds its rounding error).
    const float span = float(kTileSize - 1);
    const f32v dx_far = simd::max(simd::abs(s.mean_x - x0), simd::abs(s.mean_x - (x0 + span)));
    const f32v dy_far = simd::max(simd::abs(s.mean_y - y0), simd::abs(s.mean_y - (y0 + span)));
    const f32v size = a * dx_far * dx_far + 2.0f * simd::abs(b) * dx_far * dy_far + c * dy_far * dy_far;
    const f32v blend_limit = s.q_max * (1 + 1e-3f) + 1e-2f + 1e-5f * size;
    const f32v limit = blend_limit * (1 + 1e-4f) + 1e-4f;
    const f32v top = simd::sqrt(limit * a / det_);  // Y: the ellipse's half-height in dy
    const f32v skew = b / a;
    x_top_ = -skew * top;
    x_bottom_ = skew * top;
    c_limit_ = c * limit;
    inverse_c_ = 1.0f / c;
    // A degenerate conic (hand-made in tests, or NaN) walks its whole box.
    regular_ = (a > 0.0f) & (c > 0.0f) & (det_ > 0.0f) & (top == top);
  }

  // The rows in which some pixel centre with dx = mean_x − x in [dx_lo, dx_hi] may draw,
  // within `box` (which they replace where the conic is degenerate).
  RowSpan column_rows(simd::f32v dx_lo, simd::f32v dx_hi, const RowSpan& box) const {
    using simd::f32v;
    const f32v b = s_.conic_b;
    const f32v x_top = simd::min(simd::max(x_top_, dx_lo), dx_hi);
    const f32v x_bottom = simd::min(simd::max(x_bottom_, dx_lo), dx_hi);
    const f32v disc_top = c_limit_ - det_ * (x_top * x_top), disc_bottom = c_limit_ - det_ * (x_bottom * x_bottom);
    const f32v root_top = simd::sqrt(simd::max(disc_top, f32v{}));
    const f32v root_bottom = simd::sqrt(simd::max(disc_bottom, f32v{}));
    const f32v dy_hi = (root_top - b * x_top) * inverse_c_, dy_lo = (-root_bottom - b * x_bottom) * inverse_c_;
    // The roots' rounding, in pixels: a few ulps of the terms that formed them, and of mean_y.
    const f32v centre = simd::abs(s_.mean_y);
    const f32v margin_hi = 1e-3f + 1e-5f * ((root_top + simd::abs(b * x_top)) * inverse_c_ + centre);
    const f32v margin_lo = 1e-3f + 1e-5f * ((root_bottom + simd::abs(b * x_bottom)) * inverse_c_ + centre);
    // y = mean_y − dy: the ellipse's top in dy is its first row.
    const f32v first = simd::ceil(s_.mean_y - dy_hi - margin_hi), last = simd::floor(s_.mean_y - dy_lo + margin_lo);
    // Where the strip misses the ellipse both discriminants are negative (either is not
    // negative where it meets it: the clamped x lies within the ellipse's x range).
    const simd::i32v misses = (disc_top < 0.0f) & (disc_bottom < 0.0f);
    const simd::i32v use = regular_ & (first == first) & (last == last);
    const f32v empty_first = box.last + 1.0f;
    return {use ? (misses ? empty_first : simd::max(first, box.first)) : box.first,
            use ? simd::min(last, box.last) : box.last};
  }

 private:
  const SplatLanes& s_;
  simd::f32v det_, x_top_, x_bottom_, c_limit_, inverse_c_;
  simd::i32v regular_;
};

}  // namespace splat
