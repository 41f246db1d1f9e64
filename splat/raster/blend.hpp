#pragma once
// Stage 3 of the rasterizer: per tile, blend its Gaussians front to back into every pixel
// through the shared compositor (splat/composite/composite.hpp).
#include <cstdint>

#include "splat/raster/bin_sort.hpp"
#include "splat/raster/project.hpp"
#include "splat/raster/render_result.hpp"

namespace splat {

// α = min(kMaxAlpha, o·exp(−½ dᵀ Σ'⁻¹ d)) at each pixel centre; α < kMinAlpha is skipped.
// Tiles run in parallel; each pixel's sum runs in one fixed order, so the image is
// bit-identical for any thread count. `result` must be sized for width x height. With
// `for_backward`, also records where each list entry blended (RasterFrame::entry_chunks),
// which blend_tiles_backward needs; a render only looked at leaves it out (a few per cent).
// How the walk takes a tile's pixels: 8-pixel chunks, two per row, or whole 16-pixel rows.
// The image, the record and every count of pixels blended are the same bits either way; the
// cost differs by CPU (see default_blend_walk).
enum class BlendWalk { kChunks, kRows };

// The walk for this CPU (SPLAT_BLEND_WALK=chunks|rows in the environment overrides it, for
// benchmarks; another value is warned about on stderr and ignored).
BlendWalk default_blend_walk();

void blend_tiles(const ProjectedGaussians& projected, const TileBins& bins, const TileGrid& grid,
                 const float background[3], bool for_backward, RenderResult& result,
                 BlendWalk walk = default_blend_walk());

// The work of one blend_tiles call, for benchmarks: the Gaussian–tile pairs the lists hold and
// how many of them could draw anything, and the pixel evaluations the walk makes.
struct BlendWorkCounts {
  std::uint64_t list_entries = 0;         // Gaussian–tile pairs in the tile lists
  std::uint64_t box_entries = 0;          // ... whose α ≥ kMinAlpha box holds a pixel of the tile
  std::uint64_t reaching_entries = 0;     // ... with a pixel of the tile at α ≥ kMinAlpha
  std::uint64_t visited_entries = 0;      // pairs set up for blending (in batches of 64)
                                          // before all the tile's pixels finished
  std::uint64_t pixel_evaluations = 0;    // pixel–Gaussian α evaluations of the walk
  std::uint64_t passing_evaluations = 0;  // ... at α ≥ kMinAlpha on a pixel still blending

  BlendWorkCounts& operator+=(const BlendWorkCounts& o) {
    list_entries += o.list_entries;
    box_entries += o.box_entries;
    reaching_entries += o.reaching_entries;
    visited_entries += o.visited_entries;
    pixel_evaluations += o.pixel_evaluations;
    passing_evaluations += o.passing_evaluations;
    return *this;
  }
};

// Counts by walking a rendered frame again with counters (single-threaded; for benchmarks).
BlendWorkCounts count_blend_work(const RenderResult& rendered, BlendWalk walk = default_blend_walk());

}  // namespace splat
