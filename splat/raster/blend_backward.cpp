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
using simd::i32v;
using simd::kLanes;
using namespace tile_walk;

// Per-pixel inputs and the reverse compositing state of one tile, kLanes pixels a chunk.
struct TileReverseState {
  CompositeReverse<f32v> reverse[kChunksPerTile];
  f32v v_pixel[kChunksPerTile][3];       // ∂L/∂C
  f32v final_transmittance[kChunksPerTile];
  f32v background_dot_v[kChunksPerTile];  // bg · ∂L/∂C
  i32v contributor_count[kChunksPerTile];  // list entries up to the last blended, per pixel
};

// Gradient sums of one Gaussian over the tile's pixels, lane-wise until the end.
struct GradAccum {
  f32v mean_x{}, mean_y{}, conic_a{}, conic_b{}, conic_c{}, opacity{}, color[3]{}, weight{};

  Splat2DGrad reduce() const {
    // Eight of the sums at once; each in reduce_add's lane order.
    const f32v first[kLanes] = {mean_x, mean_y, conic_a, conic_b, conic_c, opacity, color[0], color[1]};
    const f32v sums = simd::reduce_add_each(first);
    return {sums[0], sums[1], sums[2], sums[3], sums[4], sums[5],
            {sums[6], sums[7], simd::reduce_add(color[2])}, simd::reduce_add(weight)};
  }
};

// The exponent's cotangent v_power summed over one chunk column's rows, plain and times dy and
// dy², lane-wise. Within a column dx is the same in every row, so the five 2D gradients
// (∂power/∂mean and ∂power/∂conic, each a product of v_power with dx², dx·dy, dy², dx or dy)
// are these three sums times column constants: three additions per pixel instead of five
// products and sums, the constants applied once per column (add_to).
struct PowerSums {
  f32v plain{}, dy{}, dy2{};

  void add(f32v v_power, float row_dy) {
    plain += v_power;
    dy += v_power * row_dy;
    dy2 += v_power * (row_dy * row_dy);
  }
  // power = −½(a dx² + c dy²) − b dx dy with dx = mean_x − px, dy = mean_y − py.
  void add_to(GradAccum& acc, const Splat2D& s, const SplatColumn& column) const {
    acc.mean_x -= column.a_dx * plain + s.conic_b * dy;
    acc.mean_y -= s.conic_c * dy + column.b_dx * plain;
    acc.conic_a -= (0.5f * column.dx * column.dx) * plain;
    acc.conic_b -= column.dx * dy;
    acc.conic_c -= 0.5f * dy2;
  }
};

// Loads the tile's per-pixel forward results and cotangents. Returns the largest
// contributor count in the tile (how far back the walk starts).
int load_tile(int x0, int y0, const float background[3], const RenderResult& forward,
              const Image& v_color, TileReverseState& state) {
  const int width = forward.color.width, height = forward.color.height;
  int max_count = 0;
  for (int chunk = 0; chunk < kChunksPerTile; ++chunk) {
    const int y = y0 + chunk / kChunksPerRow;
    const int x_start = x0 + (chunk % kChunksPerRow) * kLanes;
    f32v final_t{}, v[3] = {}, bg_dot{};
    i32v count{};
    for (int lane = 0; lane < kLanes; ++lane) {
      const int x = x_start + lane;
      if (x >= width || y >= height) continue;  // outside the image: count 0, never blends
      const std::size_t p = std::size_t(y) * width + x;
      final_t[lane] = forward.final_transmittance[p];
      count[lane] = int(forward.contributor_count[p]);
      for (int c = 0; c < 3; ++c) {
        v[c][lane] = v_color.data[3 * p + c];
        bg_dot[lane] += background[c] * v[c][lane];
      }
    }
    state.reverse[chunk] = CompositeReverse<f32v>::start(final_t);
    for (int c = 0; c < 3; ++c) state.v_pixel[chunk][c] = v[c];
    state.final_transmittance[chunk] = final_t;
    state.background_dot_v[chunk] = bg_dot;
    state.contributor_count[chunk] = count;
    max_count = std::max(max_count, simd::reduce_max(count));
  }
  return max_count;
}

void blend_tile_backward(int tile_x, int tile_y, const ProjectedGaussians& projected,
                         const TileBins& bins, const TileGrid& grid, const float background[3],
                         bool zero_clamped_alpha_gradient, const RenderResult& forward, const Image& v_color,
                         std::vector<Splat2DGrad>& overlap_grads) {
  const std::vector<std::uint32_t>& entry_chunks = forward.frame.entry_chunks;
  const int x0 = tile_x * kTileSize, y0 = tile_y * kTileSize;
  const std::size_t tile = std::size_t(tile_y) * grid.tiles_x + tile_x;
  const std::uint32_t list_begin = bins.tile_start[tile], list_end = bins.tile_start[tile + 1];
  if (list_begin == list_end) return;
  TileReverseState state;
  const int max_count = load_tile(x0, y0, background, forward, v_color, state);
  // Entries no pixel reached contribute nothing.
  std::memset(static_cast<void*>(&overlap_grads[list_begin + max_count]), 0,
              (list_end - list_begin - max_count) * sizeof(Splat2DGrad));

  for (int k = max_count - 1; k >= 0; --k) {
    const std::uint32_t position = list_begin + std::uint32_t(k);
    constexpr int kPrefetchDistance = 16;
    if (k >= kPrefetchDistance)
      prefetch_splat(projected.splats[bins.gaussian_ids[position - kPrefetchDistance]]);
    const Splat2D& s = projected.splats[bins.gaussian_ids[position]];
    GradAccum acc;
    bool blended_any = false;
    // The chunks where the forward pass blended this entry (elsewhere it has no gradient), in
    // row order, both chunk columns together: a fixed order, so the sums do not depend on
    // threads, and as many independent α as the entry has chunks to overlap their chains.
    if (const std::uint32_t chunks = entry_chunks[position]; chunks != 0) {
      const f32v opacity = simd::broadcast(s.opacity);
      const f32v red = simd::broadcast(s.color[0]), green = simd::broadcast(s.color[1]),
                 blue = simd::broadcast(s.color[2]);
      static_assert(kChunksPerRow == 2, "a chunk's column is its lowest bit");
      const SplatColumn column[kChunksPerRow] = {SplatColumn(s, x0, 0), SplatColumn(s, x0, 1)};
      const ColumnExponent exponent[kChunksPerRow] = {ColumnExponent(s, column[0].dx),
                                                      ColumnExponent(s, column[1].dx)};
      constexpr int kGroup = 16;
      PowerSums power_sums[kChunksPerRow];
      int order[kChunksPerTile];
      int count = 0;
      for (std::uint32_t todo = chunks; todo != 0; todo &= todo - 1) order[count++] = __builtin_ctz(todo);
      // A group of chunks at a time: first their α (each a long chain of operations, but
      // independent of the others, so they overlap), then their reverse steps and sums.
      for (int first = 0; first < count; first += kGroup) {
        const int size = std::min(kGroup, count - first);
        f32v gaussian[kGroup], raw_alpha[kGroup], alpha[kGroup];
        i32v blended[kGroup];
        for (int g = 0; g < size; ++g) {
          const int chunk = order[first + g];
          const float dy = s.mean_y - float(y0 + chunk / kChunksPerRow);
          const f32v exponent2 = exponent[chunk % kChunksPerRow].at(dy, ColumnExponent::row_term(s, dy));
          const SplatAlpha a(opacity, exponent2);
          gaussian[g] = a.gaussian;
          raw_alpha[g] = a.raw;
          alpha[g] = a.alpha;
          // Lanes whose list reaches entry k (contributor_count counts entries 1-based).
          blended[g] = (state.contributor_count[chunk] > k) & draws(exponent2, a.alpha);
        }
        for (int g = 0; g < size; ++g) {
          if (!simd::any(blended[g])) continue;
          blended_any = true;
          const int chunk = order[first + g];
          const float dy = s.mean_y - float(y0 + chunk / kChunksPerRow);
          f32v v_alpha, v_rgb[3];
          acc.weight += composite_step_vjp(state.reverse[chunk], blended[g], alpha[g], red, green, blue,
                             state.v_pixel[chunk], state.final_transmittance[chunk],
                             state.background_dot_v[chunk], v_alpha, v_rgb);
          for (int ch = 0; ch < 3; ++ch) acc.color[ch] += v_rgb[ch];
          // α = min(kMaxAlpha, o·G): where the clamp holds, α does not depend on o or G
          // (unless the caller asked for the reference rasterizer's straight-through).
          if (zero_clamped_alpha_gradient) v_alpha = raw_alpha[g] > kMaxAlpha ? f32v{} : v_alpha;
          acc.opacity += gaussian[g] * v_alpha;
          // G = exp(power): ∂G/∂power = G, so v_power = o G v_α.
          power_sums[chunk % kChunksPerRow].add(raw_alpha[g] * v_alpha, dy);
        }
      }
      for (int c = 0; c < kChunksPerRow; ++c) power_sums[c].add_to(acc, s, column[c]);
    }
    // Sums of nothing are +0, as the reduction of untouched accumulators would give.
    overlap_grads[position] = blended_any ? acc.reduce() : Splat2DGrad{};
  }
}

}  // namespace

void blend_tiles_backward(const ProjectedGaussians& projected, const TileBins& bins,
                          const TileGrid& grid, const float background[3],
                          AlphaClampGradient clamp_gradient, const RenderResult& forward,
                          const Image& v_color, std::vector<Splat2DGrad>& overlap_grads) {
  if (forward.frame.entry_chunks.size() != bins.gaussian_ids.size())
    throw ArgumentError("blend backward: the forward result holds the walk of " +
                        std::to_string(forward.frame.entry_chunks.size()) + " tile-list entries, the lists have " +
                        std::to_string(bins.gaussian_ids.size()));
  overlap_grads.resize(bins.gaussian_ids.size());
  tbb::parallel_for(0, grid.count(), [&](int tile) {
    blend_tile_backward(tile % grid.tiles_x, tile / grid.tiles_x, projected, bins, grid,
                        background, clamp_gradient == AlphaClampGradient::kZero, forward, v_color,
                        overlap_grads);
  });
}

}  // namespace splat
