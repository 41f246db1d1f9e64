// The comparison grid's error maps and panel layout, on hand-made images.
#include <gtest/gtest.h>

#include "splat/core/error.hpp"
#include "splat/eval/comparison_grid.hpp"

namespace splat {
namespace {

TEST(EvalComparisonGrid, ErrorMapIsScaledMeanAbsoluteErrorClampedToOne) {
  Image a(2, 1, 3, 0.5f), b(2, 1, 3, 0.5f);
  b.at(0, 0, 0) = 0.5f + 0.03f;  // mean over RGB 0.01 → shown 0.04
  for (int c = 0; c < 3; ++c) b.at(1, 0, c) = 0.0f;  // error 0.5 → clamped to 1
  const Image map = error_map(a, b);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(map.at(0, 0, c), kErrorMapGain * 0.01f, 1e-6f);
    EXPECT_EQ(map.at(1, 0, c), 1.0f);
  }
}

TEST(EvalComparisonGrid, PanelsSitSideBySideInOrder) {
  const Image truth(3, 2, 3, 0.2f), a(3, 2, 3, 0.2f), b(3, 2, 3, 0.45f);
  const Image grid = comparison_grid(truth, {&a, &b});
  ASSERT_EQ(grid.width, 15);
  ASSERT_EQ(grid.height, 2);
  EXPECT_FLOAT_EQ(grid.at(1, 1, 0), 0.2f);                 // truth
  EXPECT_FLOAT_EQ(grid.at(4, 1, 0), 0.2f);                 // a
  EXPECT_FLOAT_EQ(grid.at(7, 1, 0), 0.45f);                // b
  EXPECT_FLOAT_EQ(grid.at(10, 1, 0), 0.0f);                // a's error: none
  EXPECT_NEAR(grid.at(13, 1, 0), kErrorMapGain * 0.25f, 1e-6f);  // b's error
}

TEST(EvalComparisonGrid, ThreeMethodsGiveSevenPanels) {
  const Image truth(2, 1, 3, 0.5f), a(2, 1, 3, 0.5f), b(2, 1, 3, 0.4f), c(2, 1, 3, 0.7f);
  const Image grid = comparison_grid(truth, {&a, &b, &c});
  ASSERT_EQ(grid.width, 14);
  EXPECT_FLOAT_EQ(grid.at(2, 0, 0), 0.5f);                     // a
  EXPECT_FLOAT_EQ(grid.at(4, 0, 0), 0.4f);                     // b
  EXPECT_FLOAT_EQ(grid.at(6, 0, 0), 0.7f);                     // c
  EXPECT_FLOAT_EQ(grid.at(8, 0, 0), 0.0f);                     // a's error
  EXPECT_NEAR(grid.at(10, 0, 0), kErrorMapGain * 0.1f, 1e-5f);  // b's error
  EXPECT_NEAR(grid.at(12, 0, 0), kErrorMapGain * 0.2f, 1e-5f);  // c's error
}

TEST(EvalComparisonGrid, RejectsMismatchedImages) {
  EXPECT_THROW(error_map(Image(2, 2, 3), Image(3, 2, 3)), ArgumentError);
  const Image rgb(2, 2, 3), rgba(2, 2, 4);
  EXPECT_THROW(comparison_grid(rgb, {&rgba, &rgb}), ArgumentError);
}

}  // namespace
}  // namespace splat
