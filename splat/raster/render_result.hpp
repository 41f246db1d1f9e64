#pragma once
// What one render produces: the image, and everything its backward pass needs (the per-pixel
// state and the frame's projection and tile lists), so the backward takes it explicitly.
#include <cstdint>
#include <vector>

#include "splat/core/image.hpp"
#include "splat/raster/bin_sort.hpp"
#include "splat/raster/project.hpp"

namespace splat {

// The per-Gaussian and per-tile state of one rendered frame.
struct RasterFrame {
  ProjectedGaussians projected;  // every Gaussian's splat, radius and tile rectangle
  TileBins bins;                 // each tile's front-to-back list
  TileGrid grid;
  // Per list entry (parallel to bins.gaussian_ids), the chunks of its tile in which it blended
  // some pixel (tile_walk.hpp: bit row · kChunksPerRow + column), written by blend_tiles for
  // every entry before its tile's pixels all finished. The backward visits only these.
  std::vector<std::uint32_t> entry_chunks;
};

// Wall time of each stage of a render, in milliseconds.
struct RenderTimings {
  double project_ms = 0, bin_sort_ms = 0, blend_ms = 0;
  double total_ms() const { return project_ms + bin_sort_ms + blend_ms; }
};

struct RenderResult {
  Image color;                                   // [H, W, 3] with background, not clamped
  std::vector<float> alpha;                      // [H, W] 1 − final transmittance
  std::vector<float> depth;                      // [H, W] Σ wᵢ zᵢ (divide by alpha to normalise)
  // The backward pass's per-pixel state: empty in a frame rendered only to be looked at
  // (RenderSettings::for_backward off), which need not write them.
  std::vector<float> final_transmittance;        // [H, W] T after the last blended Gaussian
  std::vector<std::uint32_t> contributor_count;  // [H, W] entries of the pixel's tile list
                                                 // up to and including its last blended one
  RasterFrame frame;                             // what the pixels were blended from
  RenderTimings timings;                         // what Rasterizer::render took for it

  void resize(int width, int height, bool for_backward = true) {
    if (color.width != width || color.height != height || color.channels != 3)
      color = Image(width, height, 3);
    const std::size_t pixels = std::size_t(width) * height;
    alpha.resize(pixels);
    depth.resize(pixels);
    final_transmittance.resize(for_backward ? pixels : 0);
    contributor_count.resize(for_backward ? pixels : 0);
  }
};

}  // namespace splat
