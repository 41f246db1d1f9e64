#include "splat/eval/quality_levels.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace splat {
namespace {

TEST(QualityLevels, EachWholeDbWithTheScoresAroundItsCrossing) {
  // Scores every 1,000 iterations: 24.1, 31.4, 33.5, 33.2 (a dip), 34.7.
  const std::vector<ScorePoint> scores = {
      {999, 5, 24.1}, {2999, 53, 31.4}, {4999, 133, 33.5}, {6999, 200, 33.2}, {7999, 265, 34.7}};
  const std::vector<QualityLevel> levels = quality_levels(scores);
  ASSERT_EQ(levels.size(), 10u);  // 25 … 34
  for (int k = 0; k < 7; ++k) {  // 25 … 31: all crossed between the first two scores
    EXPECT_EQ(levels[k].psnr, 25.0 + k);
    EXPECT_EQ(levels[k].iteration, 2999);
    EXPECT_EQ(levels[k].seconds, 53);
    EXPECT_EQ(levels[k].after_seconds, 5);
  }
  EXPECT_EQ(levels[7].psnr, 32);
  EXPECT_EQ(levels[7].iteration, 4999);
  EXPECT_EQ(levels[7].after_seconds, 53);
  EXPECT_EQ(levels[8].psnr, 33);
  EXPECT_EQ(levels[8].seconds, 133);
  // 34 dB: first reached at the last score; the interval starts at the dip's score, the last
  // one below it.
  EXPECT_EQ(levels[9].psnr, 34);
  EXPECT_EQ(levels[9].iteration, 7999);
  EXPECT_EQ(levels[9].seconds, 265);
  EXPECT_EQ(levels[9].after_seconds, 200);
}

TEST(QualityLevels, OneScoreOrNoneOrAFallingRunGiveNoLevels) {
  EXPECT_TRUE(quality_levels({}).empty());
  EXPECT_TRUE(quality_levels({{50000, 1982, 37.22}}).empty());  // --test-every 0
  EXPECT_TRUE(quality_levels({{1000, 10, 29.9}, {2000, 20, 29.5}, {3000, 30, 28.1}}).empty());
}

TEST(QualityLevels, StopAtANonFiniteScore) {
  const std::vector<QualityLevel> levels =
      quality_levels({{1000, 10, 20.5}, {2000, 20, 21.2}, {3000, 30, std::nan("")}, {4000, 40, 30.0}});
  ASSERT_EQ(levels.size(), 1u);
  EXPECT_EQ(levels[0].psnr, 21);
}

}  // namespace
}  // namespace splat
