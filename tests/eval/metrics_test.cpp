#include <gtest/gtest.h>

#include <cmath>

#include "splat/core/error.hpp"
#include "splat/eval/metrics.hpp"

namespace splat {
namespace {

TEST(Metrics, PsnrOfAKnownError) {
  Image a(4, 2, 3, 0.5f), b = a;
  for (float& v : b.data) v += 0.1f;  // MSE 0.01 → 20 dB
  EXPECT_NEAR(psnr(a, b), 20.0, 1e-4);
  EXPECT_TRUE(std::isinf(psnr(a, a)));
}

TEST(Metrics, PsnrRejectsDifferentShapes) {
  EXPECT_THROW(psnr(Image(4, 2, 3), Image(2, 4, 3)), ArgumentError);
  EXPECT_THROW(psnr(Image(4, 2, 3), Image(4, 2, 4)), ArgumentError);
}

}  // namespace
}  // namespace splat
