// The SIMD helpers that are more than one operator.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "splat/core/simd.hpp"

namespace splat {
namespace {

using simd::f32v;
using simd::kLanes;

TEST(Simd, TransposeSwapsRowsAndColumns) {
  f32v rows[kLanes];
  for (int i = 0; i < kLanes; ++i)
    for (int j = 0; j < kLanes; ++j) rows[i][j] = float(10 * i + j);
  simd::transpose(rows);
  for (int i = 0; i < kLanes; ++i)
    for (int j = 0; j < kLanes; ++j) EXPECT_EQ(rows[i][j], float(10 * j + i)) << i << ", " << j;
}

TEST(Simd, ReduceAddEachSumsInReduceAddsOrder) {
  // Values whose sum depends on the order of the additions.
  f32v v[kLanes];
  for (int i = 0; i < kLanes; ++i)
    for (int j = 0; j < kLanes; ++j) v[i][j] = (j % 2 ? 1e8f : 1.0f) * float(1 + (i * 7 + j * 3) % 11) * (j % 3 ? 1.0f : -1.0f);
  const f32v sums = simd::reduce_add_each(v);
  for (int i = 0; i < kLanes; ++i) EXPECT_EQ(sums[i], simd::reduce_add(v[i])) << i;
}

TEST(Simd, MinAndMaxAreTheConditionalExpressionsLaneByLane) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float a_values[kLanes] = {1.0f, -2.0f, nan, 3.0f, 0.0f, -0.0f, 5.0f, nan};
  const float b_values[kLanes] = {2.0f, -3.0f, 1.0f, nan, -0.0f, 0.0f, 5.0f, nan};
  f32v a, b;
  for (int i = 0; i < kLanes; ++i) a[i] = a_values[i], b[i] = b_values[i];
  const f32v lo = simd::min(a, b), hi = simd::max(a, b);
  for (int i = 0; i < kLanes; ++i) {
    const float want_lo = a[i] < b[i] ? a[i] : b[i], want_hi = a[i] > b[i] ? a[i] : b[i];
    EXPECT_EQ(std::isnan(lo[i]), std::isnan(want_lo)) << i;
    EXPECT_EQ(std::isnan(hi[i]), std::isnan(want_hi)) << i;
    if (!std::isnan(want_lo)) {
      EXPECT_EQ(lo[i], want_lo) << i;
      EXPECT_EQ(std::signbit(lo[i]), std::signbit(want_lo)) << i;
    }
    if (!std::isnan(want_hi)) {
      EXPECT_EQ(hi[i], want_hi) << i;
      EXPECT_EQ(std::signbit(hi[i]), std::signbit(want_hi)) << i;
    }
  }
}

}  // namespace
}  // namespace splat
