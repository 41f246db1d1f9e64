// Binning and sorting against a direct construction.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "splat/raster/bin_sort.hpp"

namespace splat {
namespace {

TEST(BinSort, RadixSortIsAStableSortByKey) {
  std::mt19937 rng(3);
  std::vector<std::uint32_t> keys(5000);
  for (auto& k : keys) k = rng() % 300 * 0x01010101u;  // many ties, every byte used
  std::vector<std::uint32_t> expected(keys.size());
  for (std::uint32_t i = 0; i < expected.size(); ++i) expected[i] = i;
  std::shuffle(expected.begin(), expected.end(), rng);  // the low words in no particular order
  std::vector<std::uint64_t> items, scratch;
  for (std::uint32_t id : expected) items.push_back(std::uint64_t(keys[id]) << 32 | id);
  std::stable_sort(expected.begin(), expected.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
  radix_sort_by_high_word(items, scratch);
  std::vector<std::uint32_t> ids;
  for (std::uint64_t item : items) ids.push_back(std::uint32_t(item));
  EXPECT_EQ(ids, expected);
}

TEST(BinSort, RadixSortSkipsNoDigitItNeeds) {
  // Keys sharing their top digit (the pass that is skipped) but not the lower ones.
  std::vector<std::uint64_t> items, scratch;
  for (std::uint32_t i = 0; i < 100; ++i) items.push_back(std::uint64_t(0x40000000u | ((i * 37) % 100)) << 32 | i);
  radix_sort_by_high_word(items, scratch);
  for (std::size_t k = 1; k < items.size(); ++k) EXPECT_LE(items[k - 1] >> 32, items[k] >> 32);
}

TEST(BinSort, TileListsHoldEveryOverlapFrontToBack) {
  std::mt19937 rng(4);
  const TileGrid grid{7, 5};
  ProjectedGaussians p;
  const int n = 2000;
  p.splats.resize(n);
  p.radius.assign(n, 1);
  p.tiles.resize(n);
  for (int i = 0; i < n; ++i) {
    p.splats[i].depth = 0.5f + float(rng() % 50) * 0.25f;  // ties on purpose
    const int x0 = int(rng() % 7), y0 = int(rng() % 5);
    const int x1 = std::min(7, x0 + int(rng() % 3)), y1 = std::min(5, y0 + 1 + int(rng() % 2));
    p.tiles[i] = {x0, y0, x1, y1};  // some empty (x1 == x0)
  }
  TileBins bins;
  bin_and_sort(p, grid, true, bins);
  ASSERT_EQ(bins.tile_start.size(), std::size_t(grid.count() + 1));
  for (int t = 0; t < grid.count(); ++t) {
    const int tx = t % grid.tiles_x, ty = t / grid.tiles_x;
    std::vector<std::uint32_t> expected;
    for (int i = 0; i < n; ++i) {
      const TileRect& r = p.tiles[i];
      if (tx >= r.x0 && tx < r.x1 && ty >= r.y0 && ty < r.y1) expected.push_back(i);
    }
    std::stable_sort(expected.begin(), expected.end(), [&](std::uint32_t a, std::uint32_t b) {
      return p.splats[a].depth < p.splats[b].depth;
    });
    const std::vector<std::uint32_t> got(bins.gaussian_ids.begin() + bins.tile_start[t],
                                         bins.gaussian_ids.begin() + bins.tile_start[t + 1]);
    EXPECT_EQ(got, expected) << "tile " << t;
  }
  // A frame only looked at gets the same lists and no overlaps.
  TileBins looked_at;
  bin_and_sort(p, grid, false, looked_at);
  EXPECT_EQ(looked_at.gaussian_ids, bins.gaussian_ids);
  EXPECT_EQ(looked_at.tile_start, bins.tile_start);
  EXPECT_TRUE(looked_at.entry_overlap.empty());
  EXPECT_FALSE(bins.entry_overlap.empty());
}

TEST(BinSort, NoGaussiansGivesEmptyTiles) {
  ProjectedGaussians p;
  TileBins bins;
  bin_and_sort(p, TileGrid{3, 2}, true, bins);
  EXPECT_TRUE(bins.gaussian_ids.empty());
  EXPECT_EQ(bins.tile_start, std::vector<std::uint32_t>(7, 0));
}

}  // namespace
}  // namespace splat
