// The SIMD helpers that are more than one operator.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

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

TEST(Simd, ColumnsOfRowsLoadAndStoreOnlyTheirWidthAndLanes) {
  // Widths below, at and across the block of kLanes floats; rows far apart, with guard
  // floats after each row's width that must be neither read into a column nor written.
  for (int width : {3, 8, 12, 27, 48}) {
    std::vector<float> storage(kLanes * 64, -1.0f);
    const float* rows[kLanes];
    float* out_rows[kLanes];
    std::vector<float> out(kLanes * 64, -1.0f);
    for (int l = 0; l < kLanes; ++l) {
      rows[l] = &storage[64 * l];
      out_rows[l] = &out[64 * l];
      for (int j = 0; j < width; ++j) storage[64 * l + j] = float(100 * l + j);
    }
    f32v columns[48];
    simd::load_columns(rows, width, columns);
    for (int j = 0; j < width; ++j)
      for (int l = 0; l < kLanes; ++l) ASSERT_EQ(columns[j][l], float(100 * l + j)) << width << ": " << j << ", " << l;
    const std::uint32_t lanes = 0b10110101;
    simd::store_columns(columns, width, lanes, out_rows);
    for (int l = 0; l < kLanes; ++l)
      for (int j = 0; j < 64; ++j) {
        const bool written = ((lanes >> l) & 1) && j < width;
        EXPECT_EQ(out[64 * l + j], written ? float(100 * l + j) : -1.0f) << width << ": " << l << ", " << j;
      }
  }
}

TEST(Simd, ReduceAddEachSumsInReduceAddsOrder) {
  // Values whose sum depends on the order of the additions.
  f32v v[kLanes];
  for (int i = 0; i < kLanes; ++i)
    for (int j = 0; j < kLanes; ++j) v[i][j] = (j % 2 ? 1e8f : 1.0f) * float(1 + (i * 7 + j * 3) % 11) * (j % 3 ? 1.0f : -1.0f);
  const f32v sums = simd::reduce_add_each(v);
  for (int i = 0; i < kLanes; ++i) EXPECT_EQ(sums[i], simd::reduce_add(v[i])) << i;
}

// The largest relative error of exp2_nonpositive against double exp2 over every `stride`th
// float in [lo, hi] (lo < hi <= 0; a negative float's magnitude grows with its bit pattern).
double exp2_worst_error(float hi, float lo, std::uint32_t stride) {
  const auto first = std::bit_cast<std::uint32_t>(hi), last = std::bit_cast<std::uint32_t>(lo);
  double worst = 0;
  for (std::uint32_t bits = first; bits <= last; bits += stride * kLanes) {
    f32v x;
    for (int l = 0; l < kLanes; ++l) {
      const std::uint32_t lane_bits = std::min(bits + stride * std::uint32_t(l), last);
      x[l] = std::bit_cast<float>(lane_bits);
    }
    const f32v y = simd::exp2_nonpositive(x);
    for (int l = 0; l < kLanes; ++l) {
      const double exact = std::exp2(double(x[l]));
      worst = std::max(worst, std::abs(double(y[l]) - exact) / exact);
    }
  }
  return worst;
}

// The α's exp, within 1.5 ulp of 2^x (relative error 1.70e-7 at worst, measured at every
// float to −126) down to its floor (simd::kExp2Floor), below which every input gives the
// floor's value, a normal float. Where an α can pass 1/255 (x >= −8: o <= 1, and 2^−8 < 1/255)
// every 7th float is checked, below every 101st.
TEST(Simd, Exp2NonpositiveIsWithinAnUlpAndAHalfOfExp2) {
  EXPECT_LT(exp2_worst_error(-0.0f, -8.0f, 7), 1.75e-7);
  EXPECT_LT(exp2_worst_error(-8.0f, simd::kExp2Floor, 101), 1.75e-7);
  f32v x = simd::broadcast(0.0f);
  x[1] = -1.0f;
  x[2] = -1000.0f;
  x[3] = -std::numeric_limits<float>::infinity();
  const f32v y = simd::exp2_nonpositive(x);
  EXPECT_NEAR(y[0], 1.0f, 1.2e-7f);
  EXPECT_NEAR(y[1], 0.5f, 0.6e-7f);
  const float floor_value = simd::exp2_nonpositive(simd::broadcast(simd::kExp2Floor))[0];
  EXPECT_NEAR(floor_value, std::exp2(simd::kExp2Floor), std::exp2(simd::kExp2Floor) * 2e-7f);
  EXPECT_EQ(y[2], floor_value);
  EXPECT_EQ(y[3], floor_value);  // no NaN from an infinite exponent
  EXPECT_EQ(std::fpclassify(y[3]), FP_NORMAL);
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
