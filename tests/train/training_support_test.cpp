// The finiteness check behind divergence stops: every ±∞ and NaN is found wherever it sits
// (across the reduction's blocks too), and no finite value, however large or small, is.
#include "splat/train/training_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace splat::training {
namespace {

TEST(AllFinite, FindsEveryNonFiniteValueWhereverItSits) {
  constexpr std::size_t kSize = 3 * (1 << 16) + 5;  // several blocks and a remainder
  std::vector<float> values(kSize);
  for (std::size_t i = 0; i < kSize; ++i) values[i] = std::ldexp(float(i % 7) - 3.0f, int(i % 200) - 100);
  ASSERT_TRUE(all_finite(values));
  const float bad[] = {std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                       std::numeric_limits<float>::quiet_NaN(), -std::numeric_limits<float>::quiet_NaN(),
                       std::numeric_limits<float>::signaling_NaN()};
  for (std::size_t at : {std::size_t(0), std::size_t(1 << 16) - 1, std::size_t(1 << 16), kSize / 2, kSize - 1})
    for (float b : bad) {
      std::vector<float> copy = values;
      copy[at] = b;
      EXPECT_FALSE(all_finite(copy)) << b << " at " << at;
    }
}

TEST(AllFinite, AcceptsTheExtremesOfTheFiniteFloats) {
  const std::vector<float> extremes = {std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(),
                                       std::numeric_limits<float>::min(), std::numeric_limits<float>::denorm_min(),
                                       -0.0f, 0.0f};
  EXPECT_TRUE(all_finite(extremes));
  EXPECT_TRUE(all_finite(std::vector<float>(1 << 17, std::numeric_limits<float>::max())));
  EXPECT_TRUE(all_finite(std::vector<float>{}));
}

}  // namespace
}  // namespace splat::training
