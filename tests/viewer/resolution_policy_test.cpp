// Reduced resolution while moving, full when still, and a NeRF refining level by level.
#include <gtest/gtest.h>

#include "apps/splat-viewer/resolution_policy.hpp"

namespace splat::viewer {
namespace {

TEST(ResolutionPolicy, WhileMovingPicksTheLargestLevelThatFitsTheTarget) {
  ResolutionPolicy policy({0.25f, 0.5f, 1.0f}, 33.0, false);
  EXPECT_EQ(policy.next(true, 0), 0.25f);  // nothing measured yet: start coarse
  policy.observe(1.0f, 20.0);              // full resolution takes 20 ms: fits
  EXPECT_EQ(policy.next(true, 0), 1.0f);
  ResolutionPolicy slow({0.25f, 0.5f, 1.0f}, 33.0, false);
  slow.observe(0.5f, 25.0);  // 100 ms at full: half (25 ms) fits, full does not
  EXPECT_EQ(slow.next(true, 0), 0.5f);
  slow.observe(0.5f, 60.0);  // slower now: the estimate follows
  EXPECT_EQ(slow.next(true, 0), 0.25f);
}

TEST(ResolutionPolicy, StillGoesStraightToFullOrRefinesStepByStep) {
  ResolutionPolicy splat({0.25f, 0.5f, 1.0f}, 33.0, false);
  EXPECT_EQ(splat.next(false, 0.25f), 1.0f);
  ResolutionPolicy nerf({0.25f, 0.5f, 1.0f}, 33.0, true);
  EXPECT_EQ(nerf.next(false, 0.0f), 0.25f);
  EXPECT_EQ(nerf.next(false, 0.25f), 0.5f);
  EXPECT_EQ(nerf.next(false, 0.5f), 1.0f);
  EXPECT_EQ(nerf.next(false, 1.0f), 1.0f);
}

TEST(ResolutionPolicy, FullResolutionIsAlwaysALevel) {
  ResolutionPolicy policy({0.5f, 0.25f}, 33.0, true);
  ASSERT_EQ(policy.levels().size(), 3u);
  EXPECT_EQ(policy.levels().front(), 0.25f);
  EXPECT_EQ(policy.levels().back(), 1.0f);
}

}  // namespace
}  // namespace splat::viewer
