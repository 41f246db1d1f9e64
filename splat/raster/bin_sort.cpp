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
// The overlap list is filled by this many chunks of the depth order in parallel. Fixed, not
// the thread count, so the work split (and so the result) never depends on the machine.
constexpr std::size_t kFillChunks = 8;

// Positive IEEE floats order like their bit patterns; depths are > kNearPlane > 0.
std::uint32_t depth_key(float depth) {
  std::uint32_t bits;
  std::memcpy(&bits, &depth, sizeof(bits));
  return bits;
}

}  // namespace

void radix_sort_by_key(const std::vector<std::uint32_t>& keys, std::vector<std::uint32_t>& ids,
                       std::vector<std::uint32_t>& scratch) {
  scratch.resize(ids.size());
  for (int shift = 0; shift < 32; shift += kRadixBits) {
    std::array<std::uint32_t, kRadixBuckets> offsets{};
    for (std::uint32_t id : ids) ++offsets[(keys[id] >> shift) & (kRadixBuckets - 1)];
    std::uint32_t sum = 0;
    for (auto& o : offsets) {
      const std::uint32_t c = o;
      o = sum;
      sum += c;
    }
    for (std::uint32_t id : ids) scratch[offsets[(keys[id] >> shift) & (kRadixBuckets - 1)]++] = id;
    ids.swap(scratch);
  }
}

void bin_and_sort(const ProjectedGaussians& projected, const TileGrid& grid, TileBins& bins) {
  const std::size_t n = projected.splats.size();
  const std::size_t tile_count = std::size_t(grid.count());

  // 1. Gaussians that touch a tile, sorted front to back (ties keep index order).
  std::vector<std::uint32_t>& order = bins.depth_order;
  order.clear();
  for (std::size_t i = 0; i < n; ++i)
    if (projected.tiles[i].count() > 0) order.push_back(std::uint32_t(i));
  // Keys indexed by Gaussian id; only the visible ones are read.
  std::vector<std::uint32_t>& keys = bins.depth_keys;
  keys.resize(n);
  for (std::uint32_t id : order) keys[id] = depth_key(projected.splats[id].depth);
  radix_sort_by_key(keys, order, bins.sort_scratch);

  // Each Gaussian's first slot in the inverse map.
  bins.overlap_start.resize(n + 1);
  bins.overlap_start[0] = 0;
  for (std::size_t i = 0; i < n; ++i)
    bins.overlap_start[i + 1] = bins.overlap_start[i] + std::uint32_t(projected.tiles[i].count());

  // 2. The rectangles and first slots in depth order, gathered once: the passes below then
  //    read them in order instead of missing the cache on every Gaussian twice.
  bins.depth_rects.resize(order.size());
  bins.depth_overlap_start.resize(order.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order.size(), 4096), [&](const auto& range) {
    constexpr std::size_t kPrefetchDistance = 16;
    for (std::size_t k = range.begin(); k != range.end(); ++k) {
      if (k + kPrefetchDistance < order.size()) {
        __builtin_prefetch(&projected.tiles[order[k + kPrefetchDistance]]);
        __builtin_prefetch(&bins.overlap_start[order[k + kPrefetchDistance]]);
      }
      bins.depth_rects[k] = projected.tiles[order[k]];
      bins.depth_overlap_start[k] = bins.overlap_start[order[k]];
    }
  });

  // 3. Count overlaps per tile for each chunk of the depth order.
  const std::size_t chunk_size = (order.size() + kFillChunks - 1) / kFillChunks;
  std::vector<std::uint32_t>& counts = bins.chunk_counts;  // [chunk, tile]
  counts.assign(kFillChunks * tile_count, 0);
  tbb::parallel_for(std::size_t(0), kFillChunks, [&](std::size_t chunk) {
    std::uint32_t* chunk_counts = &counts[chunk * tile_count];
    const std::size_t end = std::min(order.size(), (chunk + 1) * chunk_size);
    for (std::size_t k = chunk * chunk_size; k < end; ++k) {
      const TileRect& r = bins.depth_rects[k];
      for (int ty = r.y0; ty < r.y1; ++ty)
        for (int tx = r.x0; tx < r.x1; ++tx) ++chunk_counts[std::size_t(ty) * grid.tiles_x + tx];
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
  bins.overlap_position.resize(total);

  // 5. Fill, each chunk into its own slots.
  tbb::parallel_for(std::size_t(0), kFillChunks, [&](std::size_t chunk) {
    std::uint32_t* next = &counts[chunk * tile_count];
    const std::size_t end = std::min(order.size(), (chunk + 1) * chunk_size);
    for (std::size_t k = chunk * chunk_size; k < end; ++k) {
      const std::uint32_t id = order[k];
      const TileRect& r = bins.depth_rects[k];
      std::uint32_t* positions = &bins.overlap_position[bins.depth_overlap_start[k]];
      for (int ty = r.y0; ty < r.y1; ++ty)
        for (int tx = r.x0; tx < r.x1; ++tx) {
          const std::uint32_t position = next[std::size_t(ty) * grid.tiles_x + tx]++;
          bins.gaussian_ids[position] = id;
          *positions++ = position;
        }
    }
  });
}

}  // namespace splat
