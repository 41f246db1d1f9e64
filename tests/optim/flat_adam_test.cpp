// FlatAdam: the first steps against the update rule written out by hand, and a quadratic
// that it minimises.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "splat/core/error.hpp"
#include "splat/optim/flat_adam.hpp"

namespace splat {
namespace {

TEST(FlatAdam, FirstStepsFollowTheRule) {
  FlatAdam adam(2);
  std::vector<float> p = {1.0f, -2.0f};
  const std::vector<float> g1 = {0.5f, -4.0f}, g2 = {0.25f, 1.0f};
  adam.step(p, g1, 0.1f);
  // Step 1: m = 0.1 g, v = 0.001 g², corrected m̂ = g, v̂ = g²: p −= lr·g/(|g| + ε) = lr·sign(g).
  EXPECT_NEAR(p[0], 1.0 - 0.1, 1e-6);
  EXPECT_NEAR(p[1], -2.0 + 0.1, 1e-6);
  adam.step(p, g2, 0.1f);
  for (int i = 0; i < 2; ++i) {
    const double m = 0.9 * 0.1 * g1[i] + 0.1 * g2[i];
    const double v = 0.999 * 0.001 * g1[i] * g1[i] + 0.001 * g2[i] * g2[i];
    const double update = 0.1 / (1 - 0.81) * m / (std::sqrt(v) / std::sqrt(1 - 0.999 * 0.999) + 1e-7);
    const double before = i == 0 ? 0.9 : -1.9;
    EXPECT_NEAR(p[i], before - update, 1e-5) << i;
  }
  EXPECT_EQ(adam.steps(), 2);
}

TEST(FlatAdam, MinimisesAQuadratic) {
  FlatAdam adam(3);
  std::vector<float> p = {3.0f, -1.0f, 0.5f}, g(3);
  const float target[3] = {0.5f, 0.25f, -2.0f};
  for (int it = 0; it < 2000; ++it) {
    for (int i = 0; i < 3; ++i) g[i] = 2 * (p[i] - target[i]);
    adam.step(p, g, 0.01f);
  }
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(p[i], target[i], 1e-2) << i;
}

TEST(FlatAdam, RejectsMismatchedSizes) {
  FlatAdam adam(3);
  std::vector<float> p(2), g(3);
  EXPECT_THROW(adam.step(p, g, 0.1f), ArgumentError);
}

}  // namespace
}  // namespace splat
