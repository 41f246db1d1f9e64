#include "splat/raster/blend.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <tbb/parallel_for.h>

#include "splat/composite/composite.hpp"
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

// Pixels beyond the image border (partial tiles) start finished. Returns the chunks with a
// live pixel, bit `chunk` for each.
std::uint32_t start_tile(int x0, int y0, int width, int height, TileState& state) {
  std::uint32_t live_chunks = 0;
  for (int chunk = 0; chunk < kChunksPerTile; ++chunk) {
    const int y = y0 + chunk / kChunksPerRow;
    const int x = x0 + (chunk % kChunksPerRow) * kLanes;
    state.accum[chunk] = CompositeAccum<f32v>::start();
    state.last_blended[chunk] = i32v{};
    state.finished[chunk] = ((lane_index() + float(x)) >= float(width)) | (i32v{} - int(y >= height));
    live_chunks |= std::uint32_t(simd::any(~state.finished[chunk])) << chunk;
  }
  return live_chunks;
}

// Stores the first `lanes` lanes of v at dst. A whole chunk (nearly every chunk) is one
// fixed-size store; a variable-length memcpy compiles to `rep movs`, whose start-up cost made
// writing the tile a fifth of a frame.
template <class Element, class Vector>
void store_lanes(Element* dst, const Vector& v, int lanes) {
  static_assert(sizeof(Vector) == kLanes * sizeof(Element));
  if (lanes == kLanes) {
    std::memcpy(dst, &v, sizeof(v));
    return;
  }
  for (int lane = 0; lane < lanes; ++lane) dst[lane] = Element(v[lane]);
}

// The backward's per-pixel state (final T and contributor count) only when `for_backward`.
void write_tile(int x0, int y0, const TileState& state, const float background[3], bool for_backward,
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
    // The colour image is interleaved: three planar vectors become 3 · kLanes floats.
    f32v interleaved[3];
    for (int lane = 0; lane < kLanes; ++lane)
      for (int ch = 0; ch < 3; ++ch) interleaved[(3 * lane + ch) / kLanes][(3 * lane + ch) % kLanes] = rgb[ch][lane];
    for (int part = 0; part < 3; ++part)
      store_lanes(&result.color.data[3 * p0 + part * kLanes], interleaved[part],
                  std::clamp(3 * lanes - part * kLanes, 0, kLanes));
    // The planar outputs hold the chunk's pixels contiguously.
    store_lanes(&result.alpha[p0], alpha, lanes);
    store_lanes(&result.depth[p0], a.depth, lanes);
    if (!for_backward) continue;
    store_lanes(&result.final_transmittance[p0], a.transmittance, lanes);
    store_lanes(&result.contributor_count[p0], state.last_blended[chunk], lanes);
  }
}

// What a walk over the tiles does besides the image: kRecord also records where each entry
// blended (RasterFrame::entry_chunks, for the backward pass); kCount also tallies the work
// into BlendWorkCounts, walking every list to its end (the blend itself is the same). Separate
// instantiations, so a render only looked at carries neither.
enum class BlendPass { kImage, kRecord, kCount };

// The tile's list is blended a batch at a time: first each splat of the batch is entered in
// the chunks it may draw in, then each chunk blends its entries with its state in registers,
// so the state is loaded and stored once per batch instead of once per splat and row.
constexpr int kBatch = 64;  // entries per chunk are a 64-bit mask
static_assert(kChunksPerTile <= 32, "live chunks are a 32-bit mask");

struct TileBatch {
  int size = 0;
  const Splat2D* splat[kBatch];
  std::int32_t position[kBatch];            // list position + 1 (contributor_count)
  std::uint32_t blended_chunks[kBatch];     // per entry: the chunks where it blended a pixel
  std::uint64_t entries[kChunksPerTile];    // per chunk: the entries that may draw in it
  bool reaches[kBatch];                     // (counting only) draws in some pixel
  // Per entry, the exponent's terms of each chunk column: taken once here rather than at
  // every row, it shortens the chain of operations each α waits on.
  ColumnExponent column[kBatch][kChunksPerRow];
};

// Sets up entries [k, k + batch.size) of the tile's list: each entry's chunks (eight entries
// at a time), then each chunk's entries (a bit transpose), leaving out the chunks not in `live`.
void fill_batch(const ProjectedGaussians& projected, const TileBins& bins, std::uint32_t k,
                std::uint32_t list_begin, int x0, int y0, std::uint32_t live, TileBatch& batch) {
  for (int j = 0; j < batch.size; ++j) {
    constexpr std::uint32_t kPrefetchDistance = 16;
    if (k + j + kPrefetchDistance < bins.gaussian_ids.size())
      prefetch_splat(projected.splats[bins.gaussian_ids[k + j + kPrefetchDistance]]);
    const Splat2D& s = projected.splats[bins.gaussian_ids[k + j]];
    batch.splat[j] = &s;
    batch.position[j] = std::int32_t(k + j - list_begin + 1);
    batch.blended_chunks[j] = 0;
    for (int c = 0; c < kChunksPerRow; ++c) batch.column[j][c] = ColumnExponent(s, column_dx(s, x0, c));
  }
  std::fill(std::begin(batch.entries), std::end(batch.entries), 0);
  for (int j0 = 0; j0 < batch.size; j0 += kLanes) {
    const i32v chunks = chunks_to_walk(&batch.splat[j0], std::min(kLanes, batch.size - j0), x0, y0) &
                        std::int32_t(live);
    for (std::uint32_t todo = live; todo != 0; todo &= todo - 1) {
      const int chunk = __builtin_ctz(todo);
      const i32v has = (chunks << (31 - chunk)) < 0;  // bit `chunk` moved to the sign
      batch.entries[chunk] |= std::uint64_t(simd::bits(has)) << j0;
    }
  }
}

// Blends chunk `chunk`'s entries of the batch into its state. Returns false once every pixel
// of the chunk has finished (the rest of the list cannot change it).
// The entries go kAlphaGroup at a time: first their α, then their compositing in list order
// (a short chain through T, carried from entry to entry).

template <BlendPass kPass>
bool blend_chunk(int chunk, int x0, int y0, int width, int height, TileBatch& batch,
                 TileState& state, BlendWorkCounts* counts) {
  constexpr bool kCount = kPass == BlendPass::kCount;
  const int row = chunk / kChunksPerRow, column = chunk % kChunksPerRow;
  const float y = float(y0 + row);
  CompositeAccum<f32v> accum = state.accum[chunk];
  i32v finished = state.finished[chunk];
  i32v last_blended = state.last_blended[chunk];
  for (std::uint64_t todo = batch.entries[chunk]; todo != 0;) {
    int group[kAlphaGroup];
    f32v alpha[kAlphaGroup];
    i32v passes[kAlphaGroup];
    int size = 0;
    for (; size < kAlphaGroup && todo != 0; ++size, todo &= todo - 1) {
      const int j = __builtin_ctzll(todo);
      const Splat2D& s = *batch.splat[j];
      const float dy = s.mean_y - y;
      const f32v exponent2 = batch.column[j][column].at(s, dy);
      group[size] = j;
      alpha[size] = alpha_of(simd::broadcast(s.opacity), exponent2);
      passes[size] = draws(exponent2, alpha[size]);
    }
    for (int g = 0; g < size; ++g) {
      const int j = group[g];
      const Splat2D& s = *batch.splat[j];
      const i32v live = ~finished;
      if constexpr (kCount) {
        const f32v lane_x = lane_index() + float(x0 + column * kLanes);
        if (simd::any(passes[g] & (lane_x < float(width)) & (i32v{} - int(y0 + row < height))))
          batch.reaches[j] = true;
        if (simd::any(live)) counts->pixel_evaluations += kLanes;
        counts->passing_evaluations += simd::count(live & passes[g]);
      }
      const i32v blended = composite_step(accum, live & passes[g], alpha[g], simd::broadcast(s.color[0]),
                                          simd::broadcast(s.color[1]), simd::broadcast(s.color[2]),
                                          simd::broadcast(s.depth), finished);
      last_blended = blended ? (i32v{} + batch.position[j]) : last_blended;
      if constexpr (kPass == BlendPass::kRecord) batch.blended_chunks[j] |= std::uint32_t(simd::any(blended)) << chunk;
    }
    // Once every pixel has finished, a step changes nothing, so one test per group suffices.
    if (!kCount && !simd::any(~finished)) break;
  }
  state.accum[chunk] = accum;
  state.finished[chunk] = finished;
  state.last_blended[chunk] = last_blended;
  return simd::any(~finished);
}

// `entry_chunks` is written under kRecord, `counts` under kCount.
template <BlendPass kPass>
void blend_tile(int tile_x, int tile_y, const ProjectedGaussians& projected, const TileBins& bins,
                const TileGrid& grid, const float background[3], RenderResult& result,
                std::uint32_t* entry_chunks, BlendWorkCounts* counts) {
  constexpr bool kCount = kPass == BlendPass::kCount;
  const int width = result.color.width, height = result.color.height;
  const int x0 = tile_x * kTileSize, y0 = tile_y * kTileSize;
  TileState state;
  std::uint32_t live_chunks = start_tile(x0, y0, width, height, state);
  constexpr std::uint32_t all_chunks = std::uint32_t((1ull << kChunksPerTile) - 1);

  const std::size_t tile = std::size_t(tile_y) * grid.tiles_x + tile_x;
  const std::uint32_t list_begin = bins.tile_start[tile], list_end = bins.tile_start[tile + 1];
  TileBatch batch;
  for (std::uint32_t k = list_begin; k < list_end && (kCount || live_chunks != 0); k += kBatch) {
    batch.size = int(std::min<std::uint32_t>(kBatch, list_end - k));
    // Counting walks every chunk of every entry (for the reaching count); the blend of a
    // finished chunk changes nothing, so the image is the same.
    const std::uint32_t chunks = kCount ? all_chunks : live_chunks;
    fill_batch(projected, bins, k, list_begin, x0, y0, chunks, batch);
    if constexpr (kCount) {
      counts->list_entries += std::uint32_t(batch.size);
      if (live_chunks != 0) counts->visited_entries += std::uint32_t(batch.size);
      for (int j = 0; j < batch.size; ++j) batch.reaches[j] = false;
      for (int j0 = 0; j0 < batch.size; j0 += kLanes) {
        const int count = std::min(kLanes, batch.size - j0);
        const TileBox box(SplatLanes(&batch.splat[j0], count), x0, y0);
        counts->box_entries += std::uint32_t(__builtin_popcount(simd::bits(box.inside) & ((1u << count) - 1)));
      }
    }
    for (std::uint32_t todo = chunks; todo != 0; todo &= todo - 1) {
      const int chunk = __builtin_ctz(todo);
      if (!blend_chunk<kPass>(chunk, x0, y0, width, height, batch, state, counts))
        live_chunks &= ~(1u << chunk);
    }
    // For the backward pass: it need visit only these chunks (where nothing was blended, an
    // entry has no gradient).
    if constexpr (kPass == BlendPass::kRecord)
      for (int j = 0; j < batch.size; ++j) entry_chunks[k + j] = batch.blended_chunks[j];
    if constexpr (kCount)
      for (int j = 0; j < batch.size; ++j) counts->reaching_entries += batch.reaches[j];
  }
  write_tile(x0, y0, state, background, kPass != BlendPass::kImage, result);
}

}  // namespace

void blend_tiles(const ProjectedGaussians& projected, const TileBins& bins, const TileGrid& grid,
                 const float background[3], bool for_backward, RenderResult& result) {
  std::vector<std::uint32_t>& entry_chunks = result.frame.entry_chunks;
  // Without the record the vector is empty, so a backward pass refuses the frame.
  entry_chunks.resize(for_backward ? bins.gaussian_ids.size() : 0);
  tbb::parallel_for(0, grid.count(), [&](int tile) {
    const int tile_x = tile % grid.tiles_x, tile_y = tile / grid.tiles_x;
    if (for_backward)
      blend_tile<BlendPass::kRecord>(tile_x, tile_y, projected, bins, grid, background, result,
                                     entry_chunks.data(), nullptr);
    else
      blend_tile<BlendPass::kImage>(tile_x, tile_y, projected, bins, grid, background, result,
                                    nullptr, nullptr);
  });
}

BlendWorkCounts count_blend_work(const RenderResult& rendered) {
  RenderResult scratch;
  scratch.resize(rendered.color.width, rendered.color.height);
  const float background[3] = {0, 0, 0};
  const RasterFrame& frame = rendered.frame;
  BlendWorkCounts total;
  for (int tile = 0; tile < frame.grid.count(); ++tile)
    blend_tile<BlendPass::kCount>(tile % frame.grid.tiles_x, tile / frame.grid.tiles_x, frame.projected,
                     frame.bins, frame.grid, background, scratch, nullptr, &total);
  return total;
}

}  // namespace splat
