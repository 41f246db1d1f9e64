#include "splat/raster/blend.hpp"

#include <algorithm>
#if defined(__x86_64__) || defined(__i386__)
#include <cpuid.h>
#endif
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <type_traits>
#include <tbb/parallel_for.h>

#include "splat/composite/composite.hpp"
#include "splat/raster/tile_walk.hpp"

namespace splat {

namespace {

using simd::f32v;
using simd::i32v;
using simd::kLanes;
using namespace tile_walk;

// The forward walks a tile in units: 8-pixel chunks (two per row) or whole 16-pixel rows
// (BlendWalk). Lane for lane the two compute the same α and the same sums (the exponent's
// terms and simd::exp2_nonpositive give 8 and 16 lanes the same results), so the image and
// the backward's record are the same bits either way; only the cost differs by CPU.
template <int kUnitLanes>
struct WalkUnit {
  static_assert(kUnitLanes == kLanes || kUnitLanes == simd::kRowLanes);
  using F = std::conditional_t<kUnitLanes == kLanes, f32v, simd::f32x16>;
  using M = std::conditional_t<kUnitLanes == kLanes, i32v, simd::i32x16>;
  static constexpr int kPerRow = kTileSize / kUnitLanes;
  static constexpr int kPerTile = kTileSize * kPerRow;
  static constexpr int kChunksPerUnit = kUnitLanes / kLanes;

  // The chunks (tile_walk's 8-pixel units, whose bits the backward's record uses) of unit u.
  static constexpr std::uint32_t chunks_of(int u) {
    return ((1u << kChunksPerUnit) - 1) << (u * kChunksPerUnit);
  }
  // dx = mean_x − pixel x of the unit column's lanes.
  static F dx(const Splat2D& s, int x0, int column) {
    if constexpr (kChunksPerUnit == 1)
      return column_dx(s, x0, column);
    else
      return row_dx(s, x0);
  }
  // The chunks of unit u in which some lane of `blended` is set.
  static std::uint32_t blended_chunks(M blended, int u) {
    if constexpr (kChunksPerUnit == 1)
      return std::uint32_t(simd::any(blended)) << u;
    else
      return (std::uint32_t(simd::any(simd::low_half(blended))) |
              std::uint32_t(simd::any(simd::high_half(blended))) << 1)
             << (u * kChunksPerUnit);
  }
};

// The running state of one tile's 256 pixels, a unit at a time.
template <int kUnitLanes>
struct TileState {
  using Unit = WalkUnit<kUnitLanes>;
  CompositeAccum<typename Unit::F> accum[Unit::kPerTile];
  typename Unit::M finished[Unit::kPerTile];     // lanes done (T would drop too low, or outside image)
  typename Unit::M last_blended[Unit::kPerTile];  // list position + 1 of the last Gaussian blended
};

// Pixels beyond the image border (partial tiles) start finished. Returns the units with a
// live pixel, bit `unit` for each.
template <int kUnitLanes>
std::uint32_t start_tile(int x0, int y0, int width, int height, TileState<kUnitLanes>& state) {
  using Unit = WalkUnit<kUnitLanes>;
  using F = typename Unit::F;
  using M = typename Unit::M;
  std::uint32_t live_units = 0;
  for (int u = 0; u < Unit::kPerTile; ++u) {
    const int y = y0 + u / Unit::kPerRow;
    const int x = x0 + (u % Unit::kPerRow) * kUnitLanes;
    state.accum[u] = CompositeAccum<F>::start();
    state.last_blended[u] = M{};
    state.finished[u] = ((lane_index<F>() + float(x)) >= float(width)) | (M{} - int(y >= height));
    live_units |= std::uint32_t(simd::any(~state.finished[u])) << u;
  }
  return live_units;
}

// Chunk `chunk` (8 pixels) of a tile's state: the unit itself, or half of a row.
struct ChunkState {
  CompositeAccum<f32v> accum;
  i32v last_blended;
};
inline ChunkState chunk_state(const TileState<kLanes>& state, int chunk) {
  return {state.accum[chunk], state.last_blended[chunk]};
}
inline ChunkState chunk_state(const TileState<simd::kRowLanes>& state, int chunk) {
  const int row = chunk / kChunksPerRow;
  const bool high = chunk % kChunksPerRow != 0;
  auto half = [high](auto v) { return high ? simd::high_half(v) : simd::low_half(v); };
  const CompositeAccum<simd::f32x16>& a = state.accum[row];
  ChunkState c;
  c.accum.transmittance = half(a.transmittance);
  for (int ch = 0; ch < 3; ++ch) c.accum.color[ch] = half(a.color[ch]);
  c.accum.depth = half(a.depth);
  c.last_blended = half(state.last_blended[row]);
  return c;
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
template <int kUnitLanes>
void write_tile(int x0, int y0, const TileState<kUnitLanes>& state, const float background[3], bool for_backward,
                RenderResult& result) {
  const int width = result.color.width, height = result.color.height;
  for (int chunk = 0; chunk < kChunksPerTile; ++chunk) {
    const int y = y0 + chunk / kChunksPerRow;
    if (y >= height) break;
    const int x_first = x0 + (chunk % kChunksPerRow) * kLanes;
    const int lanes = std::min(kLanes, width - x_first);
    if (lanes <= 0) continue;
    const ChunkState c = chunk_state(state, chunk);
    const CompositeAccum<f32v>& a = c.accum;
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
    store_lanes(&result.contributor_count[p0], c.last_blended, lanes);
  }
}

// What a walk over the tiles does besides the image: kRecord also records where each entry
// blended (RasterFrame::entry_chunks, for the backward pass); kCount also tallies the work
// into BlendWorkCounts, walking every list to its end (the blend itself is the same). Separate
// instantiations, so a render only looked at carries neither.
enum class BlendPass { kImage, kRecord, kCount };

// The tile's list is blended a batch at a time: first each splat of the batch is entered in
// the units it may draw in, then each unit blends its entries with its state in registers,
// so the state is loaded and stored once per batch instead of once per splat and row.
constexpr int kBatch = 64;  // entries per unit are a 64-bit mask
static_assert(kChunksPerTile <= 32, "live chunks are a 32-bit mask");

template <int kUnitLanes>
struct TileBatch {
  using Unit = WalkUnit<kUnitLanes>;
  int size = 0;
  const Splat2D* splat[kBatch];
  std::int32_t position[kBatch];            // list position + 1 (contributor_count)
  std::uint32_t blended_chunks[kBatch];     // per entry: the chunks where it blended a pixel
  std::uint64_t entries[Unit::kPerTile];    // per unit: the entries that may draw in it
  bool reaches[kBatch];                     // (counting only) draws in some pixel
  // Per entry, the exponent's terms of each unit column: taken once here rather than at
  // every row, it shortens the chain of operations each α waits on.
  ExponentTerms<typename Unit::F> column[kBatch][Unit::kPerRow];
};

// Sets up entries [k, k + batch.size) of the tile's list: each entry's chunks (eight entries
// at a time), then each unit's entries (a bit transpose), leaving out the units not in `live`.
template <int kUnitLanes>
void fill_batch(const ProjectedGaussians& projected, const TileBins& bins, std::uint32_t k,
                std::uint32_t list_begin, int x0, int y0, std::uint32_t live, TileBatch<kUnitLanes>& batch) {
  using Unit = WalkUnit<kUnitLanes>;
  for (int j = 0; j < batch.size; ++j) {
    constexpr std::uint32_t kPrefetchDistance = 16;
    if (k + j + kPrefetchDistance < bins.gaussian_ids.size())
      prefetch_splat(projected.splats[bins.gaussian_ids[k + j + kPrefetchDistance]]);
    const Splat2D& s = projected.splats[bins.gaussian_ids[k + j]];
    batch.splat[j] = &s;
    batch.position[j] = std::int32_t(k + j - list_begin + 1);
    batch.blended_chunks[j] = 0;
    for (int c = 0; c < Unit::kPerRow; ++c) batch.column[j][c] = ExponentTerms<typename Unit::F>(s, Unit::dx(s, x0, c));
  }
  std::fill(std::begin(batch.entries), std::end(batch.entries), 0);
  for (int j0 = 0; j0 < batch.size; j0 += kLanes) {
    const i32v chunks = chunks_to_walk(&batch.splat[j0], std::min(kLanes, batch.size - j0), x0, y0);
    for (std::uint32_t todo = live; todo != 0; todo &= todo - 1) {
      const int u = __builtin_ctz(todo);
      const i32v has = (chunks & std::int32_t(Unit::chunks_of(u))) != 0;
      batch.entries[u] |= std::uint64_t(simd::bits(has)) << j0;
    }
  }
}

// Blends unit `u`'s entries of the batch into its state. Returns false once every pixel
// of the unit has finished (the rest of the list cannot change it).
// The entries go kAlphaGroup at a time: first their α, then their compositing in list order
// (a short chain through T, carried from entry to entry).
template <BlendPass kPass, int kUnitLanes>
bool blend_unit(int u, int x0, int y0, int width, int height, TileBatch<kUnitLanes>& batch,
                TileState<kUnitLanes>& state, BlendWorkCounts* counts) {
  using Unit = WalkUnit<kUnitLanes>;
  using F = typename Unit::F;
  using M = typename Unit::M;
  constexpr bool kCount = kPass == BlendPass::kCount;
  const int row = u / Unit::kPerRow, column = u % Unit::kPerRow;
  const float y = float(y0 + row);
  CompositeAccum<F> accum = state.accum[u];
  M finished = state.finished[u];
  M last_blended = state.last_blended[u];
  for (std::uint64_t todo = batch.entries[u]; todo != 0;) {
    int group[kAlphaGroup];
    F alpha[kAlphaGroup];
    M passes[kAlphaGroup];
    int size = 0;
    for (; size < kAlphaGroup && todo != 0; ++size, todo &= todo - 1) {
      const int j = __builtin_ctzll(todo);
      const Splat2D& s = *batch.splat[j];
      const float dy = s.mean_y - y;
      const F exponent2 = batch.column[j][column].at(s, dy);
      group[size] = j;
      alpha[size] = alpha_of(F{} + s.opacity, exponent2);
      passes[size] = draws(exponent2, alpha[size]);
    }
    for (int g = 0; g < size; ++g) {
      const int j = group[g];
      const Splat2D& s = *batch.splat[j];
      const M live = ~finished;
      if constexpr (kCount) {
        const F lane_x = lane_index<F>() + float(x0 + column * kUnitLanes);
        if (simd::any(passes[g] & (lane_x < float(width)) & (M{} - int(y0 + row < height))))
          batch.reaches[j] = true;
        if (simd::any(live)) counts->pixel_evaluations += kUnitLanes;
        counts->passing_evaluations += simd::count(live & passes[g]);
      }
      const M blended = composite_step(accum, live & passes[g], alpha[g], F{} + s.color[0], F{} + s.color[1],
                                       F{} + s.color[2], F{} + s.depth, finished);
      last_blended = blended ? (M{} + batch.position[j]) : last_blended;
      if constexpr (kPass == BlendPass::kRecord) batch.blended_chunks[j] |= Unit::blended_chunks(blended, u);
    }
    // Once every pixel has finished, a step changes nothing, so one test per group suffices.
    if (!kCount && !simd::any(~finished)) break;
  }
  state.accum[u] = accum;
  state.finished[u] = finished;
  state.last_blended[u] = last_blended;
  return simd::any(~finished);
}

// `entry_chunks` is written under kRecord, `counts` under kCount.
template <BlendPass kPass, int kUnitLanes>
void blend_tile(int tile_x, int tile_y, const ProjectedGaussians& projected, const TileBins& bins,
                const TileGrid& grid, const float background[3], RenderResult& result,
                std::uint32_t* entry_chunks, BlendWorkCounts* counts) {
  using Unit = WalkUnit<kUnitLanes>;
  constexpr bool kCount = kPass == BlendPass::kCount;
  const int width = result.color.width, height = result.color.height;
  const int x0 = tile_x * kTileSize, y0 = tile_y * kTileSize;
  TileState<kUnitLanes> state;
  std::uint32_t live_units = start_tile(x0, y0, width, height, state);
  constexpr std::uint32_t all_units = std::uint32_t((1ull << Unit::kPerTile) - 1);

  const std::size_t tile = std::size_t(tile_y) * grid.tiles_x + tile_x;
  const std::uint32_t list_begin = bins.tile_start[tile], list_end = bins.tile_start[tile + 1];
  TileBatch<kUnitLanes> batch;
  for (std::uint32_t k = list_begin; k < list_end && (kCount || live_units != 0); k += kBatch) {
    batch.size = int(std::min<std::uint32_t>(kBatch, list_end - k));
    // Counting walks every unit of every entry (for the reaching count); the blend of a
    // finished unit changes nothing, so the image is the same.
    const std::uint32_t units = kCount ? all_units : live_units;
    fill_batch(projected, bins, k, list_begin, x0, y0, units, batch);
    if constexpr (kCount) {
      counts->list_entries += std::uint32_t(batch.size);
      if (live_units != 0) counts->visited_entries += std::uint32_t(batch.size);
      for (int j = 0; j < batch.size; ++j) batch.reaches[j] = false;
      for (int j0 = 0; j0 < batch.size; j0 += kLanes) {
        const int count = std::min(kLanes, batch.size - j0);
        const TileBox box(SplatLanes(&batch.splat[j0], count), x0, y0);
        counts->box_entries += std::uint32_t(__builtin_popcount(simd::bits(box.inside) & ((1u << count) - 1)));
      }
    }
    for (std::uint32_t todo = units; todo != 0; todo &= todo - 1) {
      const int u = __builtin_ctz(todo);
      if (!blend_unit<kPass>(u, x0, y0, width, height, batch, state, counts)) live_units &= ~(1u << u);
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

template <int kUnitLanes>
void blend_all_tiles(const ProjectedGaussians& projected, const TileBins& bins, const TileGrid& grid,
                     const float background[3], bool for_backward, RenderResult& result) {
  std::vector<std::uint32_t>& entry_chunks = result.frame.entry_chunks;
  // Without the record the vector is empty, so a backward pass refuses the frame.
  entry_chunks.resize(for_backward ? bins.gaussian_ids.size() : 0);
  tbb::parallel_for(0, grid.count(), [&](int tile) {
    const int tile_x = tile % grid.tiles_x, tile_y = tile / grid.tiles_x;
    if (for_backward)
      blend_tile<BlendPass::kRecord, kUnitLanes>(tile_x, tile_y, projected, bins, grid, background, result,
                                                 entry_chunks.data(), nullptr);
    else
      blend_tile<BlendPass::kImage, kUnitLanes>(tile_x, tile_y, projected, bins, grid, background, result,
                                                nullptr, nullptr);
  });
}

template <int kUnitLanes>
BlendWorkCounts count_work(const RenderResult& rendered) {
  RenderResult scratch;
  scratch.resize(rendered.color.width, rendered.color.height);
  const float background[3] = {0, 0, 0};
  const RasterFrame& frame = rendered.frame;
  BlendWorkCounts total;
  for (int tile = 0; tile < frame.grid.count(); ++tile)
    blend_tile<BlendPass::kCount, kUnitLanes>(tile % frame.grid.tiles_x, tile / frame.grid.tiles_x,
                                              frame.projected, frame.bins, frame.grid, background, scratch,
                                              nullptr, &total);
  return total;
}

}  // namespace

namespace {

// Whole rows pay where a 16-lane step costs about what an 8-lane one does, which is so on the
// AMD family 26 (Zen 5) cores: full-width AVX-512 units, a 16-lane step 1.05 times an 8-lane
// one, and the conformance frame's forward blend at 800² 5.2 ms in rows against 5.6 in chunks
// (bench/HISTORY.md, issue 39, 21st session). Elsewhere chunks: on the Xeon measured a 16-lane
// step costs 1.21 times an 8-lane one, on the AMD family 25 EPYC (256-bit units) twice.
BlendWalk walk_for_this_cpu() {
#if defined(__AVX512F__) && (defined(__x86_64__) || defined(__i386__))
  unsigned eax = 0, ebx = 0, ecx = 0, edx = 0;
  if (!__get_cpuid(0, &eax, &ebx, &ecx, &edx)) return BlendWalk::kChunks;
  const bool amd = ebx == 0x68747541 && edx == 0x69746e65 && ecx == 0x444d4163;  // "AuthenticAMD"
  if (!amd || !__get_cpuid(1, &eax, &ebx, &ecx, &edx)) return BlendWalk::kChunks;
  const unsigned family = ((eax >> 8) & 0xf) + (((eax >> 8) & 0xf) == 0xf ? (eax >> 20) & 0xff : 0);
  return family >= 0x1a ? BlendWalk::kRows : BlendWalk::kChunks;
#else
  return BlendWalk::kChunks;
#endif
}

}  // namespace

BlendWalk default_blend_walk() {
  static const BlendWalk walk = [] {
    if (const char* forced = std::getenv("SPLAT_BLEND_WALK")) {
      if (std::strcmp(forced, "rows") == 0) return BlendWalk::kRows;
      if (std::strcmp(forced, "chunks") == 0) return BlendWalk::kChunks;
      // A benchmark that asked for a walk must not silently time the other one.
      std::fprintf(stderr, "warning: SPLAT_BLEND_WALK=%s is neither 'chunks' nor 'rows': the walk is this CPU's\n",
                   forced);
    }
    return walk_for_this_cpu();
  }();
  return walk;
}

void blend_tiles(const ProjectedGaussians& projected, const TileBins& bins, const TileGrid& grid,
                 const float background[3], bool for_backward, RenderResult& result, BlendWalk walk) {
  if (walk == BlendWalk::kRows)
    blend_all_tiles<simd::kRowLanes>(projected, bins, grid, background, for_backward, result);
  else
    blend_all_tiles<kLanes>(projected, bins, grid, background, for_backward, result);
}

BlendWorkCounts count_blend_work(const RenderResult& rendered, BlendWalk walk) {
  return walk == BlendWalk::kRows ? count_work<simd::kRowLanes>(rendered) : count_work<kLanes>(rendered);
}

}  // namespace splat
