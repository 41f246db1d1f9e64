#pragma once
// Stage 2 of the rasterizer: for every tile, the list of Gaussians it blends, front to back.
//
// Conceptually this sorts one (tile, depth) key per Gaussian–tile overlap with a radix sort,
// as the reference rasterizer does. Every overlap of a Gaussian shares its depth, so the
// depth digits are sorted once per Gaussian (a stable LSD radix sort of N keys instead of
// M ≥ N overlap keys) and the tile digit is then a stable counting sort of the overlaps in
// depth order. Stability makes equal depths keep Gaussian-index order, as in the reference.
#include <cstdint>
#include <vector>

#include "splat/raster/project.hpp"

namespace splat {

struct TileBins {
  std::vector<std::uint32_t> gaussian_ids;  // [M] tile after tile, each front to back
  std::vector<std::uint32_t> tile_start;    // [tiles + 1] tile t's list is [start[t], start[t+1])
  // The overlaps in Gaussian order, for the backward pass to sum each Gaussian's per-tile
  // gradients in a fixed order: Gaussian i's overlaps are [overlap_start[i], [i+1]), in the
  // row-major order of its tile rectangle, and list entry p is overlap entry_overlap[p]. The
  // blend's backward writes each entry's record at its overlap, so that the projection's
  // backward reads a Gaussian's records side by side rather than from its tiles' lists.
  std::vector<std::uint32_t> overlap_start;  // [N + 1]
  std::vector<std::uint32_t> entry_overlap;  // [M]

  // Scratch reused across frames.
  std::vector<std::uint32_t> depth_order, chunk_counts;
  std::vector<std::uint64_t> depth_pairs, sort_scratch;  // (depth key << 32 | id)
  std::vector<std::int32_t> chunk_corners;
  std::vector<TileRect> depth_rects;                 // tiles[depth_order[k]]
  std::vector<std::uint32_t> depth_overlap_start;   // overlap_start[depth_order[k]]
};

// Without `for_backward` (a frame only looked at) entry_overlap is left empty.
void bin_and_sort(const ProjectedGaussians& projected, const TileGrid& grid, bool for_backward, TileBins& bins);

// Stable LSD radix sort of `items` by their high 32 bits (ascending); `scratch` is resized as
// needed.
void radix_sort_by_high_word(std::vector<std::uint64_t>& items, std::vector<std::uint64_t>& scratch);

}  // namespace splat
