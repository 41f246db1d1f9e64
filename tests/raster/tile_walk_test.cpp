// The chunk culling of the tile walk (tile_walk.hpp, splat_reach.hpp) never skips a pixel that
// draws, and the blend's work counts agree with a brute-force count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "splat/raster/rasterizer.hpp"
#include "splat/raster/tile_walk.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

using namespace tile_walk;

struct Frame {
  GaussianModel model;
  Camera camera;
  Rasterizer rasterizer;
  RenderResult result;
};

// Random Gaussians, some a thousand times thinner along one axis (long thin ellipses at every
// angle, where rounding is worst), some large, some nearly transparent.
void render_random(Frame& f, unsigned seed, int width, int height, int count) {
  f.model = test::random_model(count, 1, seed, 1.6f, 0.003f, 0.8f);
  for (int i = 0; i < count; i += 5) f.model.log_scales[3 * i + 1] = std::log(1e-4f);
  for (int i = 0; i < count; i += 11) f.model.opacity_logits[i] = -5.3f;  // o ≈ 1/200
  f.camera = test::looking_at_origin(width, height, 3.0f, 0.9f);
  f.rasterizer.render(f.model, f.camera, RenderSettings{}, f.result);
}

// Whether any pixel centre of chunk `column` in row y draws, by the blend's own arithmetic.
bool chunk_draws(const Splat2D& s, int x0, int column, int y) {
  const float dy = s.mean_y - float(y);
  const f32v exponent2 = ColumnExponent(s, column_dx(s, x0, column)).at(s, dy);
  return simd::any(draws(exponent2, alpha_of(simd::broadcast(s.opacity), exponent2)));
}

// Walks every chunk of `splats` (up to kLanes of them) in the tile at (x0, y0) and checks
// that each chunk left out holds no pixel that draws. Returns {chunks checked, chunks
// drawing, chunks left out}.
struct WalkTally {
  std::size_t checked = 0, drawing = 0, left_out = 0;
};

void check_walk(const Splat2D* const splats[kLanes], int count, int x0, int y0, WalkTally& tally) {
  const i32v walked = chunks_to_walk(splats, count, x0, y0);
  for (int l = 0; l < kLanes; ++l) {
    if (l >= count) {
      ASSERT_EQ(walked[l], 0) << "lane " << l << " beyond the " << count << " splats";
      continue;
    }
    for (int chunk = 0; chunk < kChunksPerTile; ++chunk) {
      const int y = y0 + chunk / kChunksPerRow, column = chunk % kChunksPerRow;
      const bool drawn = chunk_draws(*splats[l], x0, column, y);
      ++tally.checked;
      tally.drawing += drawn;
      if (std::uint32_t(walked[l]) >> chunk & 1) continue;
      ++tally.left_out;
      const Splat2D& s = *splats[l];
      ASSERT_FALSE(drawn) << "tile (" << x0 << ", " << y0 << ") chunk " << chunk << ": splat at (" << s.mean_x
                          << ", " << s.mean_y << ") conic " << s.conic_a << " " << s.conic_b << " "
                          << s.conic_c << " q_max " << s.q_max;
    }
  }
}

TEST(TileWalk, ChunksLeftOutNeverHoldAPixelThatDraws) {
  WalkTally tally;
  for (unsigned seed = 1; seed <= 3; ++seed) {
    Frame f;
    render_random(f, seed, 160, 128, 400);
    const TileGrid& grid = f.result.frame.grid;
    const TileBins& bins = f.result.frame.bins;
    for (int tile = 0; tile < grid.count(); ++tile) {
      const int x0 = (tile % grid.tiles_x) * kTileSize, y0 = (tile / grid.tiles_x) * kTileSize;
      for (std::uint32_t k = bins.tile_start[tile]; k < bins.tile_start[tile + 1]; k += kLanes) {
        const Splat2D* splats[kLanes];
        const int count = int(std::min<std::uint32_t>(kLanes, bins.tile_start[tile + 1] - k));
        for (int l = 0; l < count; ++l) splats[l] = &f.result.frame.projected.splats[bins.gaussian_ids[k + l]];
        check_walk(splats, count, x0, y0, tally);
        if (HasFatalFailure()) return;
      }
    }
  }
  // The scenes must exercise both sides: chunks that draw, and chunks the walk leaves out.
  EXPECT_GT(tally.drawing, tally.checked / 10);
  EXPECT_GT(tally.left_out, tally.checked / 2);
}

// Splats made directly, not through a projection: ellipses from round to 10⁴ : 1 before the
// projection's dilation, at every angle, from a pixel to a thousand pixels long, centred anywhere in and around the tile and
// far from the origin (where mean_y's own rounding is largest), at opacities from the
// threshold up, and degenerate ones. None may lose a chunk that draws.
TEST(TileWalk, ExtremeSplatsNeverLoseAChunkThatDraws) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  WalkTally tally;
  std::vector<Splat2D> splats(kLanes);
  for (int round = 0; round < 20000; ++round) {
    const int x0 = 16 * int(unit(rng) * 4000), y0 = 16 * int(unit(rng) * 4000);
    for (Splat2D& s : splats) {
      const float major = std::exp(unit(rng) * std::log(1000.0f));          // σ, pixels
      const float minor = major / std::exp(unit(rng) * std::log(1e4f));
      const float angle = unit(rng) * 3.14159265f, cos_t = std::cos(angle), sin_t = std::sin(angle);
      // Σ' = R diag(major², minor²) Rᵀ + 0.3 I (the projection's dilation, which keeps every
      // splat at least half a pixel wide); the conic is its inverse.
      const double xx = double(major) * major * cos_t * cos_t + double(minor) * minor * sin_t * sin_t + 0.3;
      const double yy = double(major) * major * sin_t * sin_t + double(minor) * minor * cos_t * cos_t + 0.3;
      const double xy = (double(major) * major - double(minor) * minor) * cos_t * sin_t;
      const double det = xx * yy - xy * xy;
      s = Splat2D{};
      s.conic_a = float(yy / det), s.conic_b = float(-xy / det), s.conic_c = float(xx / det);
      s.opacity = kMinAlpha * std::exp(unit(rng) * std::log(kMaxAlpha / kMinAlpha));
      s.q_max = 2.0f * std::log(s.opacity / kMinAlpha);
      const float reach = std::sqrt(s.q_max * float(std::max(xx, yy)));
      s.mean_x = float(x0) + 8.0f + (unit(rng) - 0.5f) * 2.0f * (reach + 10.0f);
      s.mean_y = float(y0) + 8.0f + (unit(rng) - 0.5f) * 2.0f * (reach + 10.0f);
      // The box is the projection's to get right; here it is generous, so that the reach is
      // what the test sees.
      s.extent_x = std::sqrt(s.q_max * float(xx)) * 1.01f + 1.0f;
      s.extent_y = std::sqrt(s.q_max * float(yy)) * 1.01f + 1.0f;
      if (unit(rng) < 0.01f) {  // degenerate: the box (here the whole tile) is all there is
        s.conic_a = unit(rng) < 0.5f ? 0.0f : -s.conic_a;
        s.extent_x = s.extent_y = 1e6f;
      }
    }
    const Splat2D* pointers[kLanes];
    for (int l = 0; l < kLanes; ++l) pointers[l] = &splats[l];
    check_walk(pointers, 1 + round % kLanes, x0, y0, tally);
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(tally.drawing, tally.checked / 20);
  EXPECT_GT(tally.left_out, tally.checked / 4);
}

TEST(TileWalk, BlendWorkCountsMatchABruteForceCount) {
  Frame f;
  render_random(f, 7, 96, 80, 300);
  const BlendWorkCounts work = count_blend_work(f.result);
  const TileGrid& grid = f.result.frame.grid;
  const TileBins& bins = f.result.frame.bins;
  const int width = f.camera.width, height = f.camera.height;

  // Pairs with a pixel (inside the image) at α ≥ kMinAlpha, pixel by pixel.
  std::uint64_t reaching = 0, box = 0;
  for (int tile = 0; tile < grid.count(); ++tile) {
    const int x0 = (tile % grid.tiles_x) * kTileSize, y0 = (tile / grid.tiles_x) * kTileSize;
    for (std::uint32_t k = bins.tile_start[tile]; k < bins.tile_start[tile + 1]; ++k) {
      const Splat2D& s = f.result.frame.projected.splats[bins.gaussian_ids[k]];
      // The box ±extent about the centre holds some pixel centre of the tile.
      bool in_box = false;
      for (int y = y0; y < y0 + kTileSize; ++y)
        for (int x = x0; x < x0 + kTileSize; ++x)
          in_box |= float(x) >= s.mean_x - s.extent_x && float(x) <= s.mean_x + s.extent_x &&
                    float(y) >= s.mean_y - s.extent_y && float(y) <= s.mean_y + s.extent_y;
      box += in_box;
      bool reaches = false;
      for (int y = y0; y < std::min(y0 + kTileSize, height) && !reaches; ++y)
        for (int x = x0; x < std::min(x0 + kTileSize, width) && !reaches; ++x) {
          const float dx = s.mean_x - float(x), dy = s.mean_y - float(y);
          const float power = -0.5f * (s.conic_a * dx * dx + s.conic_c * dy * dy) - s.conic_b * dx * dy;
          reaches = power <= 0.0f && std::min(kMaxAlpha, s.opacity * std::exp(power)) >= kMinAlpha;
        }
      reaching += reaches;
    }
  }
  EXPECT_EQ(work.list_entries, bins.gaussian_ids.size());
  EXPECT_EQ(work.box_entries, box);
  EXPECT_EQ(work.reaching_entries, reaching);
  EXPECT_LT(work.reaching_entries, work.list_entries);  // the 3σ lists hold pairs that cannot draw
  EXPECT_LE(work.visited_entries, work.list_entries);
  EXPECT_GT(work.passing_evaluations, 0u);
  EXPECT_LE(work.passing_evaluations, work.pixel_evaluations);
  EXPECT_EQ(work.pixel_evaluations % kLanes, 0u);
}

// The backward takes whole tile rows at 16 lanes where the forward blended chunks at 8: its
// α must be the forward's bit for bit (else a lane near the α ≥ 1/255 edge could count as
// blended in one pass and not in the other), so a row's exponent, α and draw test must be its
// two chunks', lane for lane.
TEST(TileWalk, RowOfSixteenLanesGivesItsTwoChunksAlphaBitForBit) {
  Frame f;
  render_random(f, 5, 160, 128, 400);
  const TileGrid& grid = f.result.frame.grid;
  const TileBins& bins = f.result.frame.bins;
  std::size_t rows = 0, drawing_lanes = 0;
  for (int tile = 0; tile < grid.count(); ++tile) {
    const int x0 = (tile % grid.tiles_x) * kTileSize, y0 = (tile / grid.tiles_x) * kTileSize;
    for (std::uint32_t k = bins.tile_start[tile]; k < bins.tile_start[tile + 1]; ++k) {
      const Splat2D& s = f.result.frame.projected.splats[bins.gaussian_ids[k]];
      const ExponentTerms<simd::f32x16> row(s, row_dx(s, x0));
      const ColumnExponent left(s, column_dx(s, x0, 0)), right(s, column_dx(s, x0, 1));
      for (int y = y0; y < y0 + kTileSize; ++y) {
        const float dy = s.mean_y - float(y);
        const simd::f32x16 e16 = row.at(s, dy);
        const f32v e_left = left.at(s, dy), e_right = right.at(s, dy);
        const SplatAlpha a16(simd::f32x16{} + s.opacity, e16);
        const SplatAlpha a_left(simd::broadcast(s.opacity), e_left), a_right(simd::broadcast(s.opacity), e_right);
        const simd::i32x16 d16 = draws(e16, a16.alpha);
        const simd::i32x16 d8 = simd::concat(draws(e_left, a_left.alpha), draws(e_right, a_right.alpha));
        const simd::f32x16 pairs[4][2] = {{e16, simd::concat(e_left, e_right)},
                                          {a16.gaussian, simd::concat(a_left.gaussian, a_right.gaussian)},
                                          {a16.raw, simd::concat(a_left.raw, a_right.raw)},
                                          {a16.alpha, simd::concat(a_left.alpha, a_right.alpha)}};
        for (const auto& pair : pairs)
          ASSERT_EQ(std::memcmp(&pair[0], &pair[1], sizeof(pair[0])), 0) << "tile " << tile << " entry " << k << " row " << y;
        ASSERT_EQ(std::memcmp(&d16, &d8, sizeof(d16)), 0) << "tile " << tile << " entry " << k << " row " << y;
        ++rows;
        for (int lane = 0; lane < simd::kRowLanes; ++lane) drawing_lanes += d16[lane] != 0;
      }
    }
  }
  EXPECT_GT(rows, 10000u);
  EXPECT_GT(drawing_lanes, rows);  // the rows hold drawing lanes, not only empty ones
}

}  // namespace
}  // namespace splat
