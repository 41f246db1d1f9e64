#pragma once
// What the per-tile forward pass (blend.cpp) and its backward (blend_backward.cpp) share: the
// layout of a tile's pixels in SIMD chunks, and the part of a tile one splat can draw in. The
// backward must re-evaluate exactly the α the forward blended, so both take α from here.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "splat/core/simd.hpp"
#include "splat/raster/project.hpp"
#include "splat/raster/raster_constants.hpp"
#include "splat/raster/splat_reach.hpp"

namespace splat::tile_walk {

using simd::f32v;
using simd::i32v;
using simd::kLanes;

// A tile row is kChunksPerRow chunks of kLanes pixels; chunk index = row * kChunksPerRow + column.
constexpr int kChunksPerRow = kTileSize / kLanes;
constexpr int kChunksPerTile = kTileSize * kChunksPerRow;
static_assert(kTileSize % kLanes == 0);

// 0, 1, 2, … in the lanes of an 8-lane chunk (or, with F = f32x16, a 16-lane row).
template <class F = f32v>
inline F lane_index() {
  F v;
  for (int i = 0; i < int(sizeof(F) / sizeof(float)); ++i) v[i] = float(i);
  return v;
}

// dx = mean_x − pixel x of each lane of chunk column `column` of the tile at x0 (d = splat
// centre − pixel centre, as in the reference rasterizer).
inline f32v column_dx(const Splat2D& s, int x0, int column) {
  return s.mean_x - (lane_index() + float(x0 + column * kLanes));
}

// The α's exponent power = −½(a dx² + c dy²) − b dx dy, taken in base 2 (power·log2 e, for
// simd::exp2_nonpositive) and split by what it depends on: the terms of dx alone are taken
// once per chunk column (or whole row), so each row costs one addition and one multiply-add
// before the exp. F is f32v for a chunk, f32x16 for a whole tile row; lane for lane the two
// compute the same.
constexpr float kLog2e = 1.44269504088896341f;

template <class F>
struct ExponentTerms {
  F base, slope;  // −½ log2e · a dx², −log2e · b dx

  ExponentTerms() = default;
  ExponentTerms(const Splat2D& s, F dx) : base((-0.5f * kLog2e * s.conic_a) * dx * dx), slope((-kLog2e * s.conic_b) * dx) {}

  // power·log2 e at row offset dy = mean_y − pixel y.
  F at(const Splat2D& s, float dy) const {
    const float row_term = (-0.5f * kLog2e * s.conic_c) * dy * dy;  // −½ log2e · c dy²
    return (base + row_term) + slope * dy;
  }
};
using ColumnExponent = ExponentTerms<f32v>;

// dx of a whole tile row: its two chunk columns' side by side.
inline simd::f32x16 row_dx(const Splat2D& s, int x0) {
  static_assert(kChunksPerRow == 2, "a row is two chunk columns");
  return simd::concat(column_dx(s, x0, 0), column_dx(s, x0, 1));
}

// The column's (or row's) terms of the exponent's gradients (the backward's).
template <class F>
struct SplatColumn {
  F dx, a_dx, b_dx;

  SplatColumn(const Splat2D& s, F dx_) : dx(dx_), a_dx(s.conic_a * dx), b_dx(s.conic_b * dx) {}
};

// α = min(kMaxAlpha, o·G) with G = exp(power) = 2^exponent2, and the intermediates its
// backward needs.
template <class F>
struct SplatAlpha {
  F gaussian, raw, alpha;  // G, o·G, the clamped α

  SplatAlpha(F opacity, F exponent2)
      : gaussian(simd::exp2_nonpositive(exponent2)), raw(opacity * gaussian), alpha(simd::min(F{} + kMaxAlpha, raw)) {}
};

template <class F>
F alpha_of(F opacity, F exponent2) {
  return SplatAlpha<F>(opacity, exponent2).alpha;
}

// The walks take α for kAlphaGroup list entries (forward) or chunks (backward) at a time, then
// use them in order. Each α is a chain of some twenty dependent operations (the exponent,
// exp, the clamp), independent of the others'; taken one at a time between the compositing
// steps, the core waits on that chain at the start of every chunk, grouped the chains overlap
// (the forward blend 8 % faster on a trained real capture, bit for bit the same).
constexpr int kAlphaGroup = 8;

// Lanes that draw: α ≥ kMinAlpha with the exponent not positive (as the reference tests; the
// base-2 exponent has the sign of power).
template <class F>
auto draws(F exponent2, F alpha) {
  return (exponent2 <= 0.0f) & (alpha >= kMinAlpha);
}

// Bit i of each lane (i < 16) to bit 2i: a chunk column's row masks to their chunks' bits.
inline simd::i32v spread_to_even_bits(simd::i32v bits) {
  bits = (bits | (bits << 8)) & 0x00ff00ff;
  bits = (bits | (bits << 4)) & 0x0f0f0f0f;
  bits = (bits | (bits << 2)) & 0x33333333;
  bits = (bits | (bits << 1)) & 0x55555555;
  return bits;
}

// Per lane, the splat's α ≥ kMinAlpha box (±extent about its centre) in the tile at (x0, y0):
// whether it holds a pixel centre of the tile, its rows clamped to the tile, and its first and
// last pixel columns (absolute, unclamped). NaN: not inside, as the comparisons are false.
struct TileBox {
  i32v inside;
  RowSpan rows;
  f32v col_lo, col_hi;

  TileBox(const SplatLanes& s, int x0, int y0) {
    const float left = float(x0), right = float(x0 + kTileSize - 1);
    const float top = float(y0), bottom = float(y0 + kTileSize - 1);
    const f32v row_lo = simd::ceil(s.mean_y - s.extent_y), row_hi = simd::floor(s.mean_y + s.extent_y);
    col_lo = simd::ceil(s.mean_x - s.extent_x), col_hi = simd::floor(s.mean_x + s.extent_x);
    inside = (row_lo <= bottom) & (row_hi >= top) & (row_lo <= row_hi) & (col_lo <= right) & (col_hi >= left) &
             (col_lo <= col_hi);
    rows = {simd::max(row_lo, simd::broadcast(top)), simd::min(row_hi, simd::broadcast(bottom))};
  }
};

// The chunks of the tile at (x0, y0) in which each of `count` splats may draw (one splat per
// lane; lanes from `count` on are 0): bit (row · kChunksPerRow + column) for each row and chunk
// column inside both the splat's α ≥ kMinAlpha box and its reach (splat_reach.hpp).
inline i32v chunks_to_walk(const Splat2D* const splats[kLanes], int count, int x0, int y0) {
  static_assert(kChunksPerRow == 2, "rows of two chunk columns are interleaved below");
  const SplatLanes s(splats, count);
  const float left = float(x0), top = float(y0);
  const TileBox box(s, x0, y0);
  const ReachLanes reach(s, left, top);
  i32v lanes;
  for (int l = 0; l < kLanes; ++l) lanes[l] = l;
  i32v chunks = (lanes < count) & box.inside;
  i32v walk{};
  for (int column = 0; column < kChunksPerRow; ++column) {
    const float first_x = float(x0 + column * kLanes), last_x = first_x + float(kLanes - 1);
    const RowSpan rows = reach.column_rows(s.mean_x - last_x, s.mean_x - first_x, box.rows);
    const i32v in_column = (box.col_lo <= last_x) & (box.col_hi >= first_x) & (rows.first <= rows.last);
    // Rows relative to the tile, clamped into it (they are inside where the span is not empty).
    const f32v last_row = f32v{} + float(kTileSize - 1);
    const i32v first = __builtin_convertvector(simd::min(simd::max(rows.first - top, f32v{}), last_row), i32v);
    const i32v last = __builtin_convertvector(simd::min(simd::max(rows.last - top, f32v{}), last_row), i32v);
    const i32v row_bits = in_column ? ((i32v{} + 2) << last) - ((i32v{} + 1) << first) : i32v{};
    walk |= spread_to_even_bits(row_bits) << column;
  }
  return chunks & walk;
}

// Tile lists are in depth order, not memory order: the walks fetch splat records some
// entries ahead, both cache lines a 52-byte record may straddle.
inline void prefetch_splat(const Splat2D& s) {
  const char* bytes = reinterpret_cast<const char*>(&s);
  __builtin_prefetch(bytes);
  __builtin_prefetch(bytes + sizeof(Splat2D) - 1);
}

}  // namespace splat::tile_walk
