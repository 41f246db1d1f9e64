#include "splat/raster/blend_backward.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <tbb/parallel_for.h>

#include "splat/composite/composite.hpp"
#include "splat/core/error.hpp"
#include "splat/core/simd.hpp"
#include "splat/raster/tile_walk.hpp"

namespace splat {

namespace {

using simd::f32v;
using simd::f32x16;
using simd::i32v;
using simd::i32x16;
using simd::kLanes;
using namespace tile_walk;

constexpr int kTilePixels = kTileSize * kTileSize;

// Per-pixel inputs and the reverse compositing state of one tile, one array of the tile's
// pixels (row by row) per quantity: chunk c's kLanes pixels start at c · kLanes, and a whole
// row's two chunks are one 16-lane vector.
struct TileReverseState {
  // (Aligned to the cache line, so no row straddles two.)
  alignas(64) float transmittance[kTilePixels];  // CompositeReverse: Tᵢ₊₁, starts at the final T
  alignas(64) float behind_dot_v[kTilePixels];   // CompositeReverse: v·Bᵢ
  alignas(64) float v_pixel[3][kTilePixels];     // ∂L/∂C
  alignas(64) float final_transmittance[kTilePixels];
  alignas(64) float background_dot_v[kTilePixels];  // bg · ∂L/∂C
  alignas(64) std::int32_t contributor_count[kTilePixels];  // list entries up to the last blended, per pixel
};

template <class V, class T>
V load(const T* p) {
  V v;
  std::memcpy(&v, p, sizeof(v));
  return v;
}
template <class V, class T>
void store(T* p, const V& v) {
  std::memcpy(p, &v, sizeof(v));
}

// Where a unit of work sits in a tile row: a chunk of the left or right column (8 lanes), or
// the whole row (16 lanes). Every sum below is kept at 16 lanes, lane i for pixel column i.
enum class Placement { kLeft, kRight, kRow };

template <Placement kPlace, class F>
f32x16 in_row(F v) {
  if constexpr (kPlace == Placement::kRow) return v;
  else if constexpr (kPlace == Placement::kLeft) return simd::concat(v, f32v{});
  else return simd::concat(f32v{}, v);
}

// The exponent's cotangent v_power summed over the rows, plain and times dy and dy², lane-wise.
// Within a pixel column dx is the same in every row, so the five 2D gradients (∂power/∂mean
// and ∂power/∂conic, each a product of v_power with dx², dx·dy, dy², dx or dy) are these three
// sums times column constants: three additions per pixel instead of five products and sums,
// the constants applied once per entry (add_to).
struct PowerSums {
  f32x16 plain{}, dy{}, dy2{};

  void add(f32x16 v_power, float row_dy) {
    plain += v_power;
    dy += v_power * row_dy;
    dy2 += v_power * (row_dy * row_dy);
  }
};

// Gradient sums of one Gaussian over the tile's pixels, lane-wise (16 lanes, one per pixel
// column) until the end.
struct GradAccum {
  f32x16 weight{}, color[3]{}, opacity{};
  PowerSums power;

  // power = −½(a dx² + c dy²) − b dx dy with dx = mean_x − px, dy = mean_y − py; the sums
  // folded to kLanes and reduced, each in reduce_add's lane order.
  Splat2DGrad reduce(const Splat2D& s, const SplatColumn<f32x16>& row) const {
    auto fold = [](f32x16 v) { return simd::low_half(v) + simd::high_half(v); };
    const f32x16 mean_x = -(row.a_dx * power.plain + s.conic_b * power.dy);
    const f32x16 mean_y = -(s.conic_c * power.dy + row.b_dx * power.plain);
    const f32x16 conic_a = -((0.5f * row.dx * row.dx) * power.plain);
    const f32x16 conic_b = -(row.dx * power.dy);
    const f32x16 conic_c = -(0.5f * power.dy2);
    const f32v first[kLanes] = {fold(mean_x), fold(mean_y), fold(conic_a), fold(conic_b),
                                fold(conic_c), fold(opacity), fold(color[0]), fold(color[1])};
    const f32v sums = simd::reduce_add_each(first);
    return {sums[0], sums[1], sums[2], sums[3], sums[4], sums[5],
            {sums[6], sums[7], simd::reduce_add(fold(color[2]))}, simd::reduce_add(fold(weight))};
  }
};

// Loads the tile's per-pixel forward results and cotangents. Returns the largest
// contributor count in the tile (how far back the walk starts).
int load_tile(int x0, int y0, const float background[3], const RenderResult& forward,
              const Image& v_color, TileReverseState& state) {
  const int width = forward.color.width, height = forward.color.height;
  int max_count = 0;
  for (int pixel = 0; pixel < kTilePixels; ++pixel) {
    const int x = x0 + pixel % kTileSize, y = y0 + pixel / kTileSize;
    float final_t = 0.0f, v[3] = {}, bg_dot = 0.0f;
    int count = 0;
    if (x < width && y < height) {  // outside the image: count 0, never blends
      const std::size_t p = std::size_t(y) * width + x;
      final_t = forward.final_transmittance[p];
      count = int(forward.contributor_count[p]);
      for (int c = 0; c < 3; ++c) {
        v[c] = v_color.data[3 * p + c];
        bg_dot += background[c] * v[c];
      }
    }
    state.transmittance[pixel] = final_t;
    state.behind_dot_v[pixel] = 0.0f;
    for (int c = 0; c < 3; ++c) state.v_pixel[c][pixel] = v[c];
    state.final_transmittance[pixel] = final_t;
    state.background_dot_v[pixel] = bg_dot;
    state.contributor_count[pixel] = count;
    max_count = std::max(max_count, count);
  }
  return max_count;
}

// What every unit of one entry shares.
struct EntryInputs {
  const Splat2D& s;
  int k;   // the entry's list position in the tile
  int y0;  // the tile's first row
  bool zero_clamped_alpha_gradient;
};

// Undoes the entry in `count` units of kPlace (chunk ids in `chunks`; a whole row by its left
// chunk), adding its gradients to `acc`. A group of units at a time: first their α (each a
// long chain of operations, but independent of the others, so they overlap), then their
// reverse steps and sums. Returns whether any lane blended.
template <Placement kPlace, class F>
bool reverse_units(const EntryInputs& in, const ExponentTerms<F>& exponent, const int* chunks, int count,
                   TileReverseState& state, GradAccum& acc) {
  using I = decltype(F{} < F{});
  const Splat2D& s = in.s;
  const F opacity = F{} + s.opacity, red = F{} + s.color[0], green = F{} + s.color[1], blue = F{} + s.color[2];
  constexpr int kGroup = kPlace == Placement::kRow ? 8 : 16;
  bool blended_any = false;
  for (int first = 0; first < count; first += kGroup) {
    const int size = std::min(kGroup, count - first);
    F gaussian[kGroup], raw_alpha[kGroup], alpha[kGroup];
    I blended[kGroup];
    float dy[kGroup];
    for (int g = 0; g < size; ++g) {
      const int chunk = chunks[first + g];
      dy[g] = s.mean_y - float(in.y0 + chunk / kChunksPerRow);
      const F exponent2 = exponent.at(s, dy[g]);
      const SplatAlpha a(opacity, exponent2);
      gaussian[g] = a.gaussian;
      raw_alpha[g] = a.raw;
      alpha[g] = a.alpha;
      // Lanes whose list reaches entry k (contributor_count counts entries 1-based).
      blended[g] = (load<I>(&state.contributor_count[chunk * kLanes]) > in.k) & draws(exponent2, a.alpha);
    }
    for (int g = 0; g < size; ++g) {
      if (!simd::any(blended[g])) continue;
      blended_any = true;
      const int chunk = chunks[first + g];
      const int p = chunk * kLanes;
      CompositeReverse<F> reverse{load<F>(&state.transmittance[p]), load<F>(&state.behind_dot_v[p])};
      const F v_pixel[3] = {load<F>(&state.v_pixel[0][p]), load<F>(&state.v_pixel[1][p]), load<F>(&state.v_pixel[2][p])};
      F v_alpha, v_rgb[3];
      const F weight = composite_step_vjp(reverse, blended[g], alpha[g], red, green, blue, v_pixel,
                                          load<F>(&state.final_transmittance[p]),
                                          load<F>(&state.background_dot_v[p]), v_alpha, v_rgb);
      store(&state.transmittance[p], reverse.transmittance);
      store(&state.behind_dot_v[p], reverse.behind_dot_v);
      acc.weight += in_row<kPlace>(weight);
      for (int ch = 0; ch < 3; ++ch) acc.color[ch] += in_row<kPlace>(v_rgb[ch]);
      // α = min(kMaxAlpha, o·G): where the clamp holds, α does not depend on o or G
      // (unless the caller asked for the reference rasterizer's straight-through).
      if (in.zero_clamped_alpha_gradient) v_alpha = raw_alpha[g] > kMaxAlpha ? F{} : v_alpha;
      acc.opacity += in_row<kPlace>(gaussian[g] * v_alpha);
      // G = exp(power): ∂G/∂power = G, so v_power = o G v_α.
      acc.power.add(in_row<kPlace>(raw_alpha[g] * v_alpha), dy[g]);
    }
  }
  return blended_any;
}

// The set bits of `bits`, lowest first, into `out`; returns how many.
int list_bits(std::uint32_t bits, int* out) {
  int count = 0;
  for (; bits != 0; bits &= bits - 1) out[count++] = __builtin_ctz(bits);
  return count;
}

void blend_tile_backward(int tile_x, int tile_y, const ProjectedGaussians& projected,
                         const TileBins& bins, const TileGrid& grid, const float background[3],
                         bool zero_clamped_alpha_gradient, const RenderResult& forward, const Image& v_color,
                         OverlapGradients& overlap) {
  const std::vector<std::uint32_t>& entry_chunks = forward.frame.entry_chunks;
  const int x0 = tile_x * kTileSize, y0 = tile_y * kTileSize;
  const std::size_t tile = std::size_t(tile_y) * grid.tiles_x + tile_x;
  const std::uint32_t list_begin = bins.tile_start[tile], list_end = bins.tile_start[tile + 1];
  if (list_begin == list_end) return;
  TileReverseState state;
  const int max_count = load_tile(x0, y0, background, forward, v_color, state);

  static_assert(kChunksPerRow == 2, "a row's chunks are bits 2r (left) and 2r + 1 (right)");
  constexpr std::uint32_t kLeftChunks = 0x55555555u;
  for (int k = max_count - 1; k >= 0; --k) {
    const std::uint32_t position = list_begin + std::uint32_t(k);
    constexpr int kPrefetchDistance = 16;
    if (k >= kPrefetchDistance) {
      prefetch_splat(projected.splats[bins.gaussian_ids[position - kPrefetchDistance]]);
      // The record's place is in Gaussian order, far from its neighbours': claim it early.
      __builtin_prefetch(&overlap.records[bins.entry_overlap[position - kPrefetchDistance]], 1);
    }
    const std::uint32_t chunks = entry_chunks[position];
    if (chunks == 0) continue;  // the forward pass blended this entry nowhere: no gradient
    const Splat2D& s = projected.splats[bins.gaussian_ids[position]];
    // The chunks where the forward pass blended this entry: rows where it blended in both
    // chunks as one 16-lane unit, then the left and the right chunks alone, each in row
    // order: a fixed order, so the sums do not depend on threads.
    const std::uint32_t rows = chunks & (chunks >> 1) & kLeftChunks;  // by their left chunk
    const std::uint32_t alone = chunks & ~(rows | rows << 1);
    int units[3][kTileSize];
    const int row_count = list_bits(rows, units[0]);
    const int left_count = list_bits(alone & kLeftChunks, units[1]);
    const int right_count = list_bits(alone & ~kLeftChunks, units[2]);

    const SplatColumn<f32x16> row(s, row_dx(s, x0));
    const ExponentTerms<f32x16> row_exponent(s, row.dx);
    const EntryInputs in{s, k, y0, zero_clamped_alpha_gradient};
    GradAccum acc;
    bool blended_any = reverse_units<Placement::kRow>(in, row_exponent, units[0], row_count, state, acc);
    if (left_count > 0)
      blended_any |= reverse_units<Placement::kLeft>(in, ColumnExponent(s, simd::low_half(row.dx)), units[1],
                                                     left_count, state, acc);
    if (right_count > 0)
      blended_any |= reverse_units<Placement::kRight>(in, ColumnExponent(s, simd::high_half(row.dx)), units[2],
                                                      right_count, state, acc);
    if (!blended_any) continue;
    const std::uint32_t j = bins.entry_overlap[position];
    overlap.records[j] = {acc.reduce(s, row), overlap.frame};
  }
}

}  // namespace

void OverlapGradients::start_frame(std::size_t overlaps) {
  records.resize(overlaps);  // new records are stamped 0, which no frame is
  if (++frame == 0) {        // after 2³² frames: clear the stamps once, rather than mistake one
    for (Record& record : records) record.frame = 0;
    frame = 1;
  }
}

void blend_tiles_backward(const ProjectedGaussians& projected, const TileBins& bins,
                          const TileGrid& grid, const float background[3],
                          AlphaClampGradient clamp_gradient, const RenderResult& forward,
                          const Image& v_color, OverlapGradients& overlap) {
  if (forward.frame.entry_chunks.size() != bins.gaussian_ids.size())
    throw ArgumentError("blend backward: the forward result holds the walk of " +
                        std::to_string(forward.frame.entry_chunks.size()) + " tile-list entries, the lists have " +
                        std::to_string(bins.gaussian_ids.size()));
  overlap.start_frame(bins.gaussian_ids.size());
  tbb::parallel_for(0, grid.count(), [&](int tile) {
    blend_tile_backward(tile % grid.tiles_x, tile / grid.tiles_x, projected, bins, grid,
                        background, clamp_gradient == AlphaClampGradient::kZero, forward, v_color,
                        overlap);
  });
}

}  // namespace splat
