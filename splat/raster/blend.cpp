#include "splat/raster/blend.hpp"

#include <algorithm>
#include <cmath>
#include <tbb/parallel_for.h>

#include "splat/composite.hpp"
#include "splat/core/simd.hpp"
#include "splat/raster/raster_constants.hpp"

namespace splat {

namespace {

using simd::f32v;
using simd::i32v;
using simd::kLanes;

f32v lane_index() {
  f32v v;
  for (int i = 0; i < kLanes; ++i) v[i] = float(i);
  return v;
}

constexpr int kChunksPerRow = kTileSize / kLanes;        // kLanes-pixel chunks in a tile row
constexpr int kChunksPerTile = kTileSize * kChunksPerRow;
static_assert(kTileSize % kLanes == 0);

// The running state of one tile's 256 pixels, kLanes at a time.
struct TileState {
  CompositeAccum<f32v> accum[kChunksPerTile];
  i32v finished[kChunksPerTile];     // lanes done (T would drop too low, or outside image)
  i32v last_blended[kChunksPerTile];  // list position + 1 of the last Gaussian blended
};

void blend_tile(int tile_x, int tile_y, const ProjectedGaussians& projected,
                const TileBins& bins, const TileGrid& grid, const float background[3],
                RenderResult& result) {
  const int width = result.color.width, height = result.color.height;
  const int x0 = tile_x * kTileSize, y0 = tile_y * kTileSize;
  const f32v lane_offsets = lane_index();

  TileState state;
  int live_pixels = 0;
  for (int chunk = 0; chunk < kChunksPerTile; ++chunk) {
    const int y = y0 + chunk / kChunksPerRow;
    const int x = x0 + (chunk % kChunksPerRow) * kLanes;
    state.accum[chunk] = CompositeAccum<f32v>::start();
    state.last_blended[chunk] = i32v{};
    const f32v lane_x = lane_offsets + float(x);
    // Pixels beyond the image border (partial tiles) start finished.
    state.finished[chunk] = (lane_x >= float(width)) | (i32v{} - int(y >= height));
    live_pixels += kLanes - simd::count(state.finished[chunk]);
  }

  const std::size_t tile = std::size_t(tile_y) * grid.tiles_x + tile_x;
  const std::uint32_t list_begin = bins.tile_start[tile], list_end = bins.tile_start[tile + 1];
  // The list is in depth order, not memory order: fetch records a few steps ahead so the
  // loads do not stall the blend.
  constexpr std::uint32_t kPrefetchDistance = 4;
  for (std::uint32_t k = list_begin; k < list_end && live_pixels > 0; ++k) {
    if (k + kPrefetchDistance < list_end)
      __builtin_prefetch(&projected.splats[bins.gaussian_ids[k + kPrefetchDistance]]);
    const Splat2D& s = projected.splats[bins.gaussian_ids[k]];
    // Only the pixels inside the α ≥ kMinAlpha box can blend anything.
    const int row_lo = std::max(y0, int(std::ceil(s.mean_y - s.extent_y)));
    const int row_hi = std::min(y0 + kTileSize - 1, int(std::floor(s.mean_y + s.extent_y)));
    const int col_lo = std::max(x0, int(std::ceil(s.mean_x - s.extent_x)));
    const int col_hi = std::min(x0 + kTileSize - 1, int(std::floor(s.mean_x + s.extent_x)));
    if (row_lo > row_hi || col_lo > col_hi) continue;
    const int chunk_lo = (col_lo - x0) / kLanes, chunk_hi = (col_hi - x0) / kLanes;
    const f32v opacity = simd::broadcast(s.opacity);
    const f32v red = simd::broadcast(s.color[0]), green = simd::broadcast(s.color[1]),
                blue = simd::broadcast(s.color[2]), depth = simd::broadcast(s.depth);
    const i32v position = i32v{} + int(k - list_begin + 1);

    for (int y = row_lo; y <= row_hi; ++y) {
      const float dy = s.mean_y - float(y);
      const float row_term = s.conic_c * dy * dy;
      for (int c = chunk_lo; c <= chunk_hi; ++c) {
        const int chunk = (y - y0) * kChunksPerRow + c;
        const i32v live = ~state.finished[chunk];
        if (!simd::any(live)) continue;
        // d = splat centre − pixel centre, as in the reference rasterizer.
        const f32v dx = s.mean_x - (lane_offsets + float(x0 + c * kLanes));
        const f32v power = -0.5f * (s.conic_a * dx * dx + row_term) - s.conic_b * dx * dy;
        const f32v alpha =
            simd::min(simd::broadcast(kMaxAlpha), opacity * simd::exp_nonpositive(power));
        const i32v contributes = live & (power <= 0.0f) & (alpha >= kMinAlpha);
        if (!simd::any(contributes)) continue;
        const i32v finished_before = state.finished[chunk];
        const i32v blended = composite_step(state.accum[chunk], contributes, alpha, red, green,
                                             blue, depth, state.finished[chunk]);
        state.last_blended[chunk] = blended ? position : state.last_blended[chunk];
        const i32v newly_finished = state.finished[chunk] & ~finished_before;
        if (simd::any(newly_finished)) live_pixels -= simd::count(newly_finished);
      }
    }
  }

  for (int chunk = 0; chunk < kChunksPerTile; ++chunk) {
    const int y = y0 + chunk / kChunksPerRow;
    if (y >= height) break;
    const CompositeAccum<f32v>& a = state.accum[chunk];
    for (int lane = 0; lane < kLanes; ++lane) {
      const int x = x0 + (chunk % kChunksPerRow) * kLanes + lane;
      if (x >= width) break;
      const std::size_t p = std::size_t(y) * width + x;
      const float t = a.transmittance[lane];
      for (int ch = 0; ch < 3; ++ch)
        result.color.data[3 * p + ch] = composite_finish(a, ch, background[ch])[lane];
      result.alpha[p] = 1.0f - t;
      result.depth[p] = a.depth[lane];
      result.final_transmittance[p] = t;
      result.contributor_count[p] = std::uint32_t(state.last_blended[chunk][lane]);
    }
  }
}

}  // namespace

void blend_tiles(const ProjectedGaussians& projected, const TileBins& bins, const TileGrid& grid,
                 const float background[3], RenderResult& result) {
  tbb::parallel_for(0, grid.count(), [&](int tile) {
    blend_tile(tile % grid.tiles_x, tile / grid.tiles_x, projected, bins, grid, background, result);
  });
}

}  // namespace splat
