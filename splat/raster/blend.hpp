#pragma once
// Stage 3 of the rasterizer: per tile, blend its Gaussians front to back into every pixel
// through the shared compositor (splat/composite.hpp).
#include "splat/raster/bin_sort.hpp"
#include "splat/raster/project.hpp"
#include "splat/raster/render_result.hpp"

namespace splat {

// α = min(kMaxAlpha, o·exp(−½ dᵀ Σ'⁻¹ d)) at each pixel centre; α < kMinAlpha is skipped.
// Tiles run in parallel; each pixel's sum runs in one fixed order, so the image is
// bit-identical for any thread count. `result` must be sized for width x height.
void blend_tiles(const ProjectedGaussians& projected, const TileBins& bins, const TileGrid& grid,
                 const float background[3], RenderResult& result);

}  // namespace splat
