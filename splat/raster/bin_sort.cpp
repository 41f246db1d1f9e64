#include "splat/raster/bin_sort.hpp"

#include "splat/core/error.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <limits>
#include <string>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace splat {

namespace {

constexpr int kRadixBits = 11;
constexpr std::uint32_t kRadixBuckets = 1u << kRadixBits;
// Binning's parallel passes (building the pairs, the depth sort's passes, counting and
// filling the overlap lists) each split their items into this many fixed parts. Fixed, not
// the thread count, so the work split (and so the result) never depends on the machine.
constexpr std::size_t kFillChunks = 8;

// Positive IEEE floats order like their bit patterns; depths are > kNearPlane > 0.
std::uint32_t depth_key(float depth) {
  std::uint32_t bits;
  std::memcpy(&bits, &depth, sizeof(bits));
  return bits;
}

}  // namespace

void radix_sort_by_high_word(std::vector<std::uint64_t>& items, std::vector<std::uint64_t>& scratch) {
  scratch.resize(items.size());
  // Each pass counts and scatters kFillChunks fixed parts of the items in parallel; part p's
  // items go after those of parts < p within every bucket, so the sort stays stable and the
  // result does not depend on the thread count.
  const std::size_t part_size = (items.size() + kFillChunks - 1) / kFillChunks;
  std::vector<std::array<std::uint32_t, kRadixBuckets>> offsets(kFillChunks);
  for (int shift = 32; shift < 64; shift += kRadixBits) {
    auto digit = [shift](std::uint64_t item) { return (item >> shift) & (kRadixBuckets - 1); };
    tbb::parallel_for(std::size_t(0), kFillChunks, [&](std::size_t part) {
      offsets[part].fill(0);
      const std::size_t end = std::min(items.size(), (part + 1) * part_size);
      for (std::size_t k = part * part_size; k < end; ++k) ++offsets[part][digit(items[k])];
    });
    // A digit every item shares (the top bits of depths in one octave) needs no pass.
    if (!items.empty()) {
      std::uint64_t with_first_digit = 0;
      for (const auto& part : offsets) with_first_digit += part[digit(items[0])];
      if (with_first_digit == items.size()) continue;
    }
    std::uint32_t sum = 0;
    for (std::uint32_t bucket = 0; bucket < kRadixBuckets; ++bucket)
      for (auto& part : offsets) {
        const std::uint32_t c = part[bucket];
        part[bucket] = sum;
        sum += c;
      }
    tbb::parallel_for(std::size_t(0), kFillChunks, [&](std::size_t part) {
      auto& next = offsets[part];
      const std::size_t end = std::min(items.size(), (part + 1) * part_size);
      for (std::size_t k = part * part_size; k < end; ++k) scratch[next[digit(items[k])]++] = items[k];
    });
    items.swap(scratch);
  }
}

void bin_and_sort(const ProjectedGaussians& projected, const TileGrid& grid, bool for_backward, TileBins& bins) {
  const std::size_t n = projected.splats.size();
  const std::size_t tile_count = std::size_t(grid.count());

  // 1. Gaussians that touch a tile, sorted front to back (ties keep index order): (depth
  //    key, id) pairs sorted by key, read in order rather than through the ids.
  //    The pairs and each Gaussian's first slot in the inverse map (overlap_start) are
  //    written by kFillChunks parts of the index range in parallel, each at offsets counted
  //    first, so both are the same as from one sequential pass.
  const std::size_t part_size = (n + kFillChunks - 1) / kFillChunks;
  std::array<std::uint64_t, kFillChunks + 1> visible_before{}, overlaps_before{};
  tbb::parallel_for(std::size_t(0), kFillChunks, [&](std::size_t part) {
    std::uint64_t visible = 0, overlaps = 0;
    for (std::size_t i = part * part_size; i < std::min(n, (part + 1) * part_size); ++i) {
      const std::int64_t count = projected.tiles[i].count();
      visible += count > 0;
      overlaps += std::uint64_t(count);
    }
    visible_before[part + 1] = visible;
    overlaps_before[part + 1] = overlaps;
  });
  for (std::size_t part = 0; part < kFillChunks; ++part) {
    visible_before[part + 1] += visible_before[part];
    overlaps_before[part + 1] += overlaps_before[part];
  }
  std::vector<std::uint64_t>& pairs = bins.depth_pairs;
  pairs.resize(visible_before[kFillChunks]);
  bins.overlap_start.resize(n + 1);
  bins.overlap_start[0] = 0;
  tbb::parallel_for(std::size_t(0), kFillChunks, [&](std::size_t part) {
    std::size_t next = visible_before[part];
    std::uint64_t slot = overlaps_before[part];
    for (std::size_t i = part * part_size; i < std::min(n, (part + 1) * part_size); ++i) {
      const std::int64_t count = projected.tiles[i].count();
      if (count > 0) pairs[next++] = std::uint64_t(depth_key(projected.splats[i].depth)) << 32 | i;
      slot += std::uint64_t(count);
      bins.overlap_start[i + 1] = std::uint32_t(slot);  // > 32 bits is an error below
    }
  });
  radix_sort_by_high_word(pairs, bins.sort_scratch);
  std::vector<std::uint32_t>& order = bins.depth_order;
  order.resize(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) order[k] = std::uint32_t(pairs[k]);

  // 2. The rectangles and first slots in depth order, gathered once: the passes below then
  //    read them in order instead of missing the cache on every Gaussian twice.
  bins.depth_rects.resize(order.size());
  bins.depth_overlap_start.resize(for_backward ? order.size() : 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order.size(), 4096), [&](const auto& range) {
    constexpr std::size_t kPrefetchDistance = 16;
    for (std::size_t k = range.begin(); k != range.end(); ++k) {
      if (k + kPrefetchDistance < order.size()) {
        __builtin_prefetch(&projected.tiles[order[k + kPrefetchDistance]]);
        if (for_backward) __builtin_prefetch(&bins.overlap_start[order[k + kPrefetchDistance]]);
      }
      bins.depth_rects[k] = projected.tiles[order[k]];
      if (for_backward) bins.depth_overlap_start[k] = bins.overlap_start[order[k]];
    }
  });

  // 3. Count overlaps per tile for each chunk of the depth order: each rectangle adds 1 at
  //    two corners and −1 at the other two of a (tiles_y + 1) × (tiles_x + 1) grid, whose
  //    2D prefix sum is then the count per tile (O(1) per Gaussian, not per overlap).
  const std::size_t chunk_size = (order.size() + kFillChunks - 1) / kFillChunks;
  const std::size_t stride = std::size_t(grid.tiles_x) + 1;
  const std::size_t corner_cells = stride * (std::size_t(grid.tiles_y) + 1);
  std::vector<std::int32_t>& corners = bins.chunk_corners;  // [chunk, corner cell]
  corners.assign(kFillChunks * corner_cells, 0);
  std::vector<std::uint32_t>& counts = bins.chunk_counts;  // [chunk, tile]
  counts.resize(kFillChunks * tile_count);
  tbb::parallel_for(std::size_t(0), kFillChunks, [&](std::size_t chunk) {
    std::int32_t* d = &corners[chunk * corner_cells];
    const std::size_t end = std::min(order.size(), (chunk + 1) * chunk_size);
    for (std::size_t k = chunk * chunk_size; k < end; ++k) {
      const TileRect& r = bins.depth_rects[k];
      ++d[r.y0 * stride + r.x0];
      --d[r.y0 * stride + r.x1];
      --d[r.y1 * stride + r.x0];
      ++d[r.y1 * stride + r.x1];
    }
    std::uint32_t* chunk_counts = &counts[chunk * tile_count];
    for (int ty = 0; ty < grid.tiles_y; ++ty) {
      std::int32_t row_sum = 0;
      for (int tx = 0; tx < grid.tiles_x; ++tx) {
        row_sum += d[ty * stride + tx];
        const std::int32_t above = ty > 0 ? std::int32_t(chunk_counts[std::size_t(ty - 1) * grid.tiles_x + tx]) : 0;
        chunk_counts[std::size_t(ty) * grid.tiles_x + tx] = std::uint32_t(above + row_sum);
      }
    }
  });

  // 4. Each chunk's write position in each tile: tiles in order, chunks in order within a
  //    tile, so the result equals one sequential stable pass.
  bins.tile_start.assign(tile_count + 1, 0);
  std::uint64_t total = 0;
  for (std::size_t t = 0; t < tile_count; ++t) {
    bins.tile_start[t] = std::uint32_t(total);
    for (std::size_t chunk = 0; chunk < kFillChunks; ++chunk) {
      std::uint32_t& c = counts[chunk * tile_count + t];
      const std::uint32_t chunk_total = c;
      c = std::uint32_t(total);  // now the chunk's next write position in tile t
      total += chunk_total;
    }
  }
  if (total > std::numeric_limits<std::uint32_t>::max())
    throw Error("rasterizer: " + std::to_string(total) +
                " Gaussian-tile overlaps exceed the 32-bit list index; render smaller");
  bins.tile_start[tile_count] = std::uint32_t(total);
  bins.gaussian_ids.resize(total);
  // A frame only looked at needs no overlaps: one scattered write stream fewer.
  bins.entry_overlap.resize(for_backward ? total : 0);

  // 5. Fill, each chunk into its own slots.
  tbb::parallel_for(std::size_t(0), kFillChunks, [&](std::size_t chunk) {
    std::uint32_t* next = &counts[chunk * tile_count];
    const std::size_t end = std::min(order.size(), (chunk + 1) * chunk_size);
    for (std::size_t k = chunk * chunk_size; k < end; ++k) {
      const std::uint32_t id = order[k];
      const TileRect& r = bins.depth_rects[k];
      std::uint32_t overlap = for_backward ? bins.depth_overlap_start[k] : 0;
      for (int ty = r.y0; ty < r.y1; ++ty)
        for (int tx = r.x0; tx < r.x1; ++tx) {
          const std::uint32_t position = next[std::size_t(ty) * grid.tiles_x + tx]++;
          bins.gaussian_ids[position] = id;
          if (for_backward) bins.entry_overlap[position] = overlap++;
        }
    }
  });
}

}  // namespace splat
