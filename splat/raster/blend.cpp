#include "splat/raster/blend.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <tbb/parallel_for.h>

#include "splat/composite.hpp"
#include "splat/raster/tile_walk.hpp"

namespace splat {

namespace {

using simd::f32v;
using simd::i32v;
using simd::kLanes;
using namespace tile_walk;

// The running state of one tile's 256 pixels, kLanes at a time.
struct TileState {
  CompositeAccum<f32v> accum[kChunksPerTile];
  i32v finished[kChunksPerTile];     // lanes done (T would drop too low, or outside image)
  i32v last_blended[kChunksPerTile];  // list position + 1 of the last Gaussian blended
};

// Pixels beyond the image border (partial tiles) start finished. Returns the live pixels.
int start_tile(int x0, int y0, int width, int height, TileState& state) {
  int live_pixels = 0;
  for (int chunk = 0; chunk < kChunksPerTile; ++chunk) {
    const int y = y0 + chunk / kChunksPerRow;
    const int x = x0 + (chunk % kChunksPerRow) * kLanes;
    state.accum[chunk] = CompositeAccum<f32v>::start();
    state.last_blended[chunk] = i32v{};
    state.finished[chunk] = ((lane_index() + float(x)) >= float(width)) | (i32v{} - int(y >= height));
    live_pixels += kLanes - simd::count(state.finished[chunk]);
  }
  return live_pixels;
}

void write_tile(int x0, int y0, const TileState& state, const float background[3],
                RenderResult& result) {
  const int width = result.color.width, height = result.color.height;
  for (int chunk = 0; chunk < kChunksPerTile; ++chunk) {
    const int y = y0 + chunk / kChunksPerRow;
    if (y >= height) break;
    const int x_first = x0 + (chunk % kChunksPerRow) * kLanes;
    const int lanes = std::min(kLanes, width - x_first);
    if (lanes <= 0) continue;
    const CompositeAccum<f32v>& a = state.accum[chunk];
    f32v rgb[3];
    for (int ch = 0; ch < 3; ++ch) rgb[ch] = composite_finish(a, ch, background[ch]);
    const f32v alpha = 1.0f - a.transmittance;
    const std::size_t p0 = std::size_t(y) * width + x_first;
    float* color = &result.color.data[3 * p0];
    for (int lane = 0; lane < lanes; ++lane)
      for (int ch = 0; ch < 3; ++ch) color[3 * lane + ch] = rgb[ch][lane];
    // The planar outputs hold the chunk's pixels contiguously.
    const std::size_t bytes = std::size_t(lanes) * sizeof(float);
    std::memcpy(&result.alpha[p0], &alpha, bytes);
    std::memcpy(&result.depth[p0], &a.depth, bytes);
    std::memcpy(&result.final_transmittance[p0], &a.transmittance, bytes);
    std::memcpy(&result.contributor_count[p0], &state.last_blended[chunk], bytes);
  }
}

// kCount: also tally the work into `counts`, walking every list to its end (the blend itself
// is the same); a separate instantiation, so the timed renders carry no counters.
template <bool kCount>
void blend_tile(int tile_x, int tile_y, const ProjectedGaussians& projected, const TileBins& bins,
                const TileGrid& grid, const float background[3], RenderResult& result,
                BlendWorkCounts* counts) {
  const int width = result.color.width, height = result.color.height;
  const int x0 = tile_x * kTileSize, y0 = tile_y * kTileSize;
  TileState state;
  int live_pixels = start_tile(x0, y0, width, height, state);

  const std::size_t tile = std::size_t(tile_y) * grid.tiles_x + tile_x;
  const std::uint32_t list_begin = bins.tile_start[tile], list_end = bins.tile_start[tile + 1];
  // The list is in depth order, not memory order: fetch records a few steps ahead so the
  // loads do not stall the blend.
  constexpr std::uint32_t kPrefetchDistance = 4;
  for (std::uint32_t k = list_begin; k < list_end && (kCount || live_pixels > 0); ++k) {
    if constexpr (kCount) {
      ++counts->list_entries;
      counts->visited_entries += live_pixels > 0;
    }
    if (k + kPrefetchDistance < list_end)
      __builtin_prefetch(&projected.splats[bins.gaussian_ids[k + kPrefetchDistance]]);
    const Splat2D& s = projected.splats[bins.gaussian_ids[k]];
    const Footprint box = footprint_in_tile(s, x0, y0);
    if (box.empty()) continue;
    const SplatReach reach(s);
    bool reaches = false;  // a pixel of the tile at α ≥ kMinAlpha (counting only)
    const f32v opacity = simd::broadcast(s.opacity);
    const f32v red = simd::broadcast(s.color[0]), green = simd::broadcast(s.color[1]),
               blue = simd::broadcast(s.color[2]), depth = simd::broadcast(s.depth);
    const i32v position = i32v{} + int(k - list_begin + 1);

    for (int c = box.chunk_lo; c <= box.chunk_hi; ++c) {
      const SplatColumn column(s, x0, c);
      for (std::uint32_t rows = rows_to_walk(s, reach, x0, y0, c, box); rows != 0; rows &= rows - 1) {
        const int y = y0 + __builtin_ctz(rows);
        const int chunk = (y - y0) * kChunksPerRow + c;
        const i32v live = ~state.finished[chunk];
        if (!kCount && !simd::any(live)) continue;
        const float dy = s.mean_y - float(y);
        const f32v power = column.power(dy, s.conic_c * dy * dy);
        const f32v alpha = alpha_of(opacity, power);
        const i32v passes = draws(power, alpha);
        if constexpr (kCount) {
          const f32v lane_x = lane_index() + float(x0 + c * kLanes);
          reaches = reaches ||
                    simd::any(passes & (lane_x < float(width)) & (i32v{} - int(y < height)));
          if (simd::any(live)) counts->pixel_evaluations += kLanes;
          counts->passing_evaluations += simd::count(live & passes);
        }
        const i32v contributes = live & passes;
        const i32v finished_before = state.finished[chunk];
        const i32v blended = composite_step(state.accum[chunk], contributes, alpha, red, green,
                                            blue, depth, state.finished[chunk]);
        state.last_blended[chunk] = blended ? position : state.last_blended[chunk];
        const i32v newly_finished = state.finished[chunk] & ~finished_before;
        if (simd::any(newly_finished)) live_pixels -= simd::count(newly_finished);
      }
    }
    if constexpr (kCount) {
      ++counts->box_entries;
      counts->reaching_entries += reaches;
    }
  }
  write_tile(x0, y0, state, background, result);
}

}  // namespace

void blend_tiles(const ProjectedGaussians& projected, const TileBins& bins, const TileGrid& grid,
                 const float background[3], RenderResult& result) {
  tbb::parallel_for(0, grid.count(), [&](int tile) {
    blend_tile<false>(tile % grid.tiles_x, tile / grid.tiles_x, projected, bins, grid, background,
                      result, nullptr);
  });
}

BlendWorkCounts count_blend_work(const RenderResult& rendered) {
  RenderResult scratch;
  scratch.resize(rendered.color.width, rendered.color.height);
  const float background[3] = {0, 0, 0};
  const RasterFrame& frame = rendered.frame;
  BlendWorkCounts total;
  for (int tile = 0; tile < frame.grid.count(); ++tile)
    blend_tile<true>(tile % frame.grid.tiles_x, tile / frame.grid.tiles_x, frame.projected,
                     frame.bins, frame.grid, background, scratch, &total);
  return total;
}

}  // namespace splat
