#pragma once
// Backward of stage 3: per tile, walk each pixel's blended Gaussians back to front through
// the shared compositor's backward and collect, per Gaussian–tile overlap, the gradient of
// the loss with respect to the Gaussian's 2D parameters.
#include <cstdint>
#include <vector>

#include "splat/core/image.hpp"
#include "splat/raster/bin_sort.hpp"
#include "splat/raster/project.hpp"
#include "splat/raster/render_result.hpp"

namespace splat {

enum class AlphaClampGradient { kZero, kStraightThrough };

// ∂L/∂(2D parameters) of one Gaussian, summed over the pixels of one tile.
struct Splat2DGrad {
  float mean_x, mean_y;             // pixel coordinates
  float conic_a, conic_b, conic_c;  // power = −½(a dx² + c dy²) − b dx dy
  float opacity;                    // the activated opacity o
  float color[3];
  // Not a gradient: Σ Tᵢαᵢ over the tile's pixels, how much of the image this Gaussian makes
  // (density control prunes by it). Computed here because the backward walk has Tᵢαᵢ anyway.
  float blend_weight;
};

// The blend's backward records, one per Gaussian–tile overlap, in Gaussian order (index
// TileBins::entry_overlap[p] for list entry p): where the entries' gradients, scattered over
// the tiles' lists, are written, so that the projection's backward reads each Gaussian's side
// by side. Only overlaps where the Gaussian blended are written, stamped with the frame
// (the others hold an older stamp and stand for zero): that spares the blend's backward a
// scattered write for every entry that blended nowhere (a third of them on real captures),
// and the stamp shares its record's cache lines, where a separate flag array would not.
// A record fills one cache line (44 bytes padded to 64): packed, most of them straddled two
// lines, and each scattered write paid for both (the blend's backward at native real_thermos
// size 40.7 → 37.7 ms, on lego400 9.6 → 8.6 ms; the projection's backward reads them no slower).
struct OverlapGradients {
  struct alignas(64) Record {  // one cache line
    Splat2DGrad grad;
    std::uint32_t frame = 0;  // the frame that wrote it
  };
  std::vector<Record> records;  // [M]
  std::uint32_t frame = 0;      // this frame's stamp, never 0 after a backward pass

  bool written(std::size_t j) const { return records[j].frame == frame; }
  // Starts a frame of `overlaps` records, none written yet.
  void start_frame(std::size_t overlaps);
};

// Fills `overlap` for every entry of every tile list. Each entry is written by exactly one tile in a fixed order,
// so the result does not depend on the thread count. `v_color` is ∂L/∂color, [H, W, 3];
// `forward` is blend_tiles' result for these lists, rendered for a backward pass (its
// per-pixel state and the chunks where each entry blended); ArgumentError otherwise.
void blend_tiles_backward(const ProjectedGaussians& projected, const TileBins& bins,
                          const TileGrid& grid, const float background[3],
                          AlphaClampGradient clamp_gradient, const RenderResult& forward,
                          const Image& v_color, OverlapGradients& overlap);

}  // namespace splat
