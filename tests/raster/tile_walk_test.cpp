// The chunk culling of the tile walk (tile_walk.hpp, splat_reach.hpp) never skips a pixel that
// draws, and the blend's work counts agree with a brute-force count.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

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

TEST(TileWalk, RowsLeftOutNeverHoldAPixelThatDraws) {
  std::size_t rows_checked = 0, rows_left_out = 0, rows_drawing = 0;
  for (unsigned seed = 1; seed <= 3; ++seed) {
    Frame f;
    render_random(f, seed, 160, 128, 400);
    const TileGrid& grid = f.result.frame.grid;
    const TileBins& bins = f.result.frame.bins;
    for (int tile = 0; tile < grid.count(); ++tile) {
      const int x0 = (tile % grid.tiles_x) * kTileSize, y0 = (tile / grid.tiles_x) * kTileSize;
      for (std::uint32_t k = bins.tile_start[tile]; k < bins.tile_start[tile + 1]; ++k) {
        const Splat2D& s = f.result.frame.projected.splats[bins.gaussian_ids[k]];
        const Footprint box = footprint_in_tile(s, x0, y0);
        if (box.empty()) continue;
        const SplatReach reach(s);
        for (int c = box.chunk_lo; c <= box.chunk_hi; ++c) {
          const std::uint32_t walked = rows_to_walk(s, reach, x0, y0, c, box);
          for (int y = box.row_lo; y <= box.row_hi; ++y) {
            const bool drawn = chunk_draws(s, x0, c, y);
            ++rows_checked;
            rows_drawing += drawn;
            if (walked >> (y - y0) & 1) continue;
            ++rows_left_out;
            ASSERT_FALSE(drawn) << "seed " << seed << " tile " << tile << " entry " << k << " row " << y;
          }
        }
      }
    }
  }
  // The scenes must exercise both sides: rows that draw, and rows the trim removes.
  EXPECT_GT(rows_drawing, rows_checked / 4);
  EXPECT_GT(rows_left_out, rows_checked / 50);
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
      box += !footprint_in_tile(s, x0, y0).empty();
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
