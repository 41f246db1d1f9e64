// The activations every parametrised value goes through (splat/core/activations.hpp).
#include "splat/core/activations.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace splat {
namespace {

TEST(Activations, LogitUndoesSigmoid) {
  for (float p : {0.005f, 0.1f, 0.5f, 0.9f, 0.99f}) EXPECT_NEAR(sigmoid(logit(p)), p, 1e-6f) << p;
  for (double p : {1e-6, 0.3, 0.999999}) EXPECT_NEAR(sigmoid(logit(p)), p, 1e-12) << p;
  EXPECT_EQ(sigmoid(0.0f), 0.5f);
  EXPECT_EQ(logit(0.5f), 0.0f);
}

TEST(Activations, TheLanesGiveTheScalarSigmoidBitForBit) {
  simd::f32v x;
  for (int l = 0; l < simd::kLanes; ++l) x[l] = -20.0f + 5.7f * float(l);
  const simd::f32v y = simd::sigmoid(x);
  for (int l = 0; l < simd::kLanes; ++l) EXPECT_EQ(y[l], sigmoid(x[l])) << x[l];
}

}  // namespace
}  // namespace splat
