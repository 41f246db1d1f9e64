// The shared compositor: forward sums, early termination, and its backward against finite
// differences in double.
#include <gtest/gtest.h>

#include "tests/gradient_check.hpp"
#include "splat/composite/composite.hpp"

namespace splat {
namespace {

constexpr double kBackground[3] = {0.3, 0.6, 0.9};

// Inputs: per sample α then (r, g, b); output the composited colour.
std::vector<double> composite(const std::vector<double>& in) {
  auto acc = CompositeAccum<double>::start();
  bool finished = false;
  for (std::size_t i = 0; i + 3 < in.size(); i += 4)
    composite_step(acc, true, in[i], in[i + 1], in[i + 2], in[i + 3], 0.0, finished);
  return {composite_finish(acc, 0, kBackground[0]), composite_finish(acc, 1, kBackground[1]),
          composite_finish(acc, 2, kBackground[2])};
}

TEST(Compositor, ForwardSumMatchesTheFormula) {
  const std::vector<double> in = {0.5, 1, 0, 0, 0.25, 0, 1, 0};
  const std::vector<double> c = composite(in);
  // C = 0.5·red + 0.5·0.25·green + 0.5·0.75·bg.
  EXPECT_NEAR(c[0], 0.5 + 0.375 * kBackground[0], 1e-15);
  EXPECT_NEAR(c[1], 0.125 + 0.375 * kBackground[1], 1e-15);
  EXPECT_NEAR(c[2], 0.375 * kBackground[2], 1e-15);
}

TEST(Compositor, StopsBeforeTransmittanceFallsBelowTheFloor) {
  auto acc = CompositeAccum<float>::start();
  bool finished = false;
  EXPECT_TRUE(composite_step(acc, true, 0.99f, 1.f, 1.f, 1.f, 2.f, finished));   // T = 0.01
  EXPECT_TRUE(composite_step(acc, true, 0.98f, 1.f, 1.f, 1.f, 2.f, finished));   // T = 2e-4
  EXPECT_FALSE(finished);
  EXPECT_FALSE(composite_step(acc, true, 0.9f, 1.f, 1.f, 1.f, 2.f, finished));   // 2e-5 < 1e-4
  EXPECT_TRUE(finished);
  EXPECT_NEAR(acc.transmittance, 2e-4f, 1e-9f);
  EXPECT_FALSE(composite_step(acc, false, 0.5f, 1.f, 1.f, 1.f, 2.f, finished));  // not offered
}

TEST(Compositor, BackwardMatchesFiniteDifferences) {
  for (unsigned seed = 1; seed <= 4; ++seed) {
    const int samples = 6;
    std::vector<double> x = test::random_vector(4 * samples, seed);
    for (int i = 0; i < samples; ++i) x[4 * i] = 0.05 + 0.8 / (1 + std::exp(-x[4 * i]));  // α in (0.05, 0.85)
    const std::vector<double> v = test::random_vector(3, seed + 50);
    // Forward for the final T, then the backward walk.
    auto acc = CompositeAccum<double>::start();
    bool finished = false;
    for (int i = 0; i < samples; ++i)
      composite_step(acc, true, x[4 * i], x[4 * i + 1], x[4 * i + 2], x[4 * i + 3], 0.0, finished);
    const double bg_dot_v = kBackground[0] * v[0] + kBackground[1] * v[1] + kBackground[2] * v[2];
    auto reverse = CompositeReverse<double>::start(acc.transmittance);
    std::vector<double> analytic(x.size());
    for (int i = samples - 1; i >= 0; --i) {
      double v_alpha, v_color[3];
      composite_step_vjp(reverse, true, x[4 * i], x[4 * i + 1], x[4 * i + 2], x[4 * i + 3], v.data(),
                         acc.transmittance, bg_dot_v, v_alpha, v_color);
      analytic[4 * i] = v_alpha;
      for (int c = 0; c < 3; ++c) analytic[4 * i + 1 + c] = v_color[c];
    }
    test::expect_vjp_matches(composite, x, v, analytic, "compositor");
    EXPECT_NEAR(reverse.transmittance, 1.0, 1e-12);  // T rebuilt back to the front
  }
}

}  // namespace
}  // namespace splat
