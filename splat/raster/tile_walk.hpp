#pragma once
// What the per-tile forward pass (blend.cpp) and its backward (blend_backward.cpp) share: the
// layout of a tile's pixels in SIMD chunks, and the part of a tile one splat can draw in. The
// backward must re-evaluate exactly the α the forward blended, so both take α from here.
#include <algorithm>
#include <cmath>
#include <cstdint>
#if defined(__BMI2__)
#include <immintrin.h>
#endif

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

inline f32v lane_index() {
  f32v v;
  for (int i = 0; i < kLanes; ++i) v[i] = float(i);
  return v;
}

// The rows and chunk columns of the tile at (x0, y0) inside a splat's α ≥ kMinAlpha box
// (rows are absolute pixel rows; columns are chunk indices within the tile row).
struct Footprint {
  int row_lo, row_hi, chunk_lo, chunk_hi;
  bool empty() const { return row_lo > row_hi || chunk_lo > chunk_hi; }
};

inline Footprint footprint_in_tile(const Splat2D& s, int x0, int y0) {
  const int row_lo = std::max(y0, int(std::ceil(s.mean_y - s.extent_y)));
  const int row_hi = std::min(y0 + kTileSize - 1, int(std::floor(s.mean_y + s.extent_y)));
  const int col_lo = std::max(x0, int(std::ceil(s.mean_x - s.extent_x)));
  const int col_hi = std::min(x0 + kTileSize - 1, int(std::floor(s.mean_x + s.extent_x)));
  if (col_lo > col_hi) return {row_lo, row_hi, 1, 0};
  return {row_lo, row_hi, (col_lo - x0) / kLanes, (col_hi - x0) / kLanes};
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

// The rows of `box` in which chunk `column` of the tile at (x0, y0) may draw, as a bit mask
// (bit r for row y0 + r). Every row of the tile is tested at once, one per lane.
inline std::uint32_t rows_to_walk(const Splat2D& s, const SplatReach& reach, int x0, int y0,
                                  int column, const Footprint& box) {
  const float dx_hi = s.mean_x - float(x0 + column * kLanes), dx_lo = dx_hi - float(kLanes - 1);
  std::uint32_t rows = 0;
  for (int r0 = 0; r0 < kTileSize; r0 += kLanes) {
    const f32v y = lane_index() + float(y0 + r0);
    const i32v walk = reach.rows_may_draw(s.mean_y - y, dx_lo, dx_hi) & (y >= float(box.row_lo)) &
                      (y <= float(box.row_hi));
    rows |= simd::bits(walk) << r0;
  }
  return rows;
}

// Tile lists are in depth order, not memory order: the walks fetch splat records some
// entries ahead, both cache lines a 52-byte record may straddle.
inline void prefetch_splat(const Splat2D& s) {
  const char* bytes = reinterpret_cast<const char*>(&s);
  __builtin_prefetch(bytes);
  __builtin_prefetch(bytes + sizeof(Splat2D) - 1);
}

// Bit i of `bits` (i < 16) to bit 2i: a chunk column's row mask to its chunks' bits.
inline std::uint32_t spread_to_even_bits(std::uint32_t bits) {
#if defined(__BMI2__)
  return _pdep_u32(bits, 0x55555555u);
#else
  bits &= 0xffffu;
  bits = (bits | (bits << 8)) & 0x00ff00ffu;
  bits = (bits | (bits << 4)) & 0x0f0f0f0fu;
  bits = (bits | (bits << 2)) & 0x33333333u;
  bits = (bits | (bits << 1)) & 0x55555555u;
  return bits;
#endif
}

}  // namespace splat::tile_walk
