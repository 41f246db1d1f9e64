// The forward blend's two walks (8-pixel chunks, whole 16-pixel rows: BlendWalk) give the same
// bits: every output image, the backward's record, and every count of what blends. Which one
// runs depends on the CPU, so both are run here whatever the machine.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "splat/raster/rasterizer.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

void poison(RenderResult& r, float value) {
  for (std::vector<float>* v : {&r.color.data, &r.alpha, &r.depth, &r.final_transmittance})
    std::fill(v->begin(), v->end(), value);
  std::fill(r.contributor_count.begin(), r.contributor_count.end(), std::uint32_t(value));
  std::fill(r.frame.entry_chunks.begin(), r.frame.entry_chunks.end(), std::uint32_t(value));
}

// Renders once (for the projection and the tile lists), then blends the frame with each walk.
struct TwoWalks {
  RenderResult chunks, rows;

  TwoWalks(int width, int height, unsigned seed, bool for_backward) {
    GaussianModel model = test::random_model(400, 1, seed, 1.6f, 0.003f, 0.8f);
    for (std::size_t i = 0; i < model.size(); i += 5) model.log_scales[3 * i + 1] = std::log(1e-4f);
    for (std::size_t i = 0; i < model.size(); i += 7) model.opacity_logits[i] = 6.0f;  // T runs out
    const Camera camera = test::looking_at_origin(width, height, 3.0f, 0.9f);
    RenderSettings settings;
    settings.for_backward = for_backward;
    Rasterizer rasterizer;
    rasterizer.render(model, camera, settings, chunks);
    rows = chunks;
    // Different leftovers in each, so an output one walk fails to write cannot compare equal.
    poison(chunks, 1.0f);
    poison(rows, 2.0f);
    const RasterFrame& frame = chunks.frame;
    blend_tiles(frame.projected, frame.bins, frame.grid, settings.background, for_backward, chunks,
                BlendWalk::kChunks);
    blend_tiles(frame.projected, frame.bins, frame.grid, settings.background, for_backward, rows,
                BlendWalk::kRows);
  }
};

void expect_same_outputs(const RenderResult& a, const RenderResult& b, bool for_backward) {
  EXPECT_TRUE(same_bits(a.color.data, b.color.data));
  EXPECT_TRUE(same_bits(a.alpha, b.alpha));
  EXPECT_TRUE(same_bits(a.depth, b.depth));
  if (!for_backward) return;
  EXPECT_TRUE(same_bits(a.final_transmittance, b.final_transmittance));
  EXPECT_TRUE(same_bits(a.contributor_count, b.contributor_count));
  EXPECT_TRUE(same_bits(a.frame.entry_chunks, b.frame.entry_chunks));
}

TEST(BlendWalk, ChunksAndRowsGiveTheSameBits) {
  // Image sizes that leave partial tiles: a partial chunk (x = 83 ends mid-chunk), a partial
  // row of chunks (x = 88 ends at a chunk boundary), whole tiles.
  const int sizes[][2] = {{83, 61}, {88, 50}, {96, 64}};
  for (const auto& size : sizes)
    for (bool for_backward : {false, true}) {
      SCOPED_TRACE(::testing::Message() << size[0] << " x " << size[1] << (for_backward ? ", recorded" : ""));
      const TwoWalks walks(size[0], size[1], 11, for_backward);
      expect_same_outputs(walks.chunks, walks.rows, for_backward);
      // Something was drawn and something reached the end of T, so the test compares work done.
      double covered = 0;
      for (float a : walks.chunks.alpha) covered += a;
      EXPECT_GT(covered, 0.05 * double(walks.chunks.alpha.size()));
      if (for_backward) {
        std::size_t recorded = 0;
        for (std::uint32_t chunks : walks.chunks.frame.entry_chunks) recorded += chunks != 0;
        EXPECT_GT(recorded, walks.chunks.frame.entry_chunks.size() / 4);
      }
    }
}

TEST(BlendWalk, CountsDifferOnlyInTheLanesEvaluated) {
  const TwoWalks walks(83, 61, 5, true);
  const BlendWorkCounts chunks = count_blend_work(walks.chunks, BlendWalk::kChunks);
  const BlendWorkCounts rows = count_blend_work(walks.rows, BlendWalk::kRows);
  EXPECT_EQ(chunks.list_entries, rows.list_entries);
  EXPECT_EQ(chunks.box_entries, rows.box_entries);
  EXPECT_EQ(chunks.reaching_entries, rows.reaching_entries);
  EXPECT_EQ(chunks.visited_entries, rows.visited_entries);
  EXPECT_EQ(chunks.passing_evaluations, rows.passing_evaluations);
  EXPECT_GT(chunks.passing_evaluations, 0u);
  // A row step evaluates both chunks of the row, where the chunk walk may skip one.
  EXPECT_GE(rows.pixel_evaluations, chunks.pixel_evaluations);
  EXPECT_LE(rows.pixel_evaluations, 2 * chunks.pixel_evaluations);
  EXPECT_EQ(rows.pixel_evaluations % 16, 0u);
}

}  // namespace
}  // namespace splat
