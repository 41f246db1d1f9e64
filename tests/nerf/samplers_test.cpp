// Stratified and hierarchical (importance) samples along a ray.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "splat/core/error.hpp"
#include "splat/nerf/samplers.hpp"

namespace splat {
namespace {

constexpr RayBounds kBounds{2.0f, 6.0f};

TEST(NerfSampler, StratifiedIsSortedOnePerBinWithinBounds) {
  const int n = 64;
  std::vector<float> t(n), delta(n);
  std::mt19937 rng(11);
  stratified_samples(kBounds, true, rng, t, delta);
  const float bin = (kBounds.far - kBounds.near) / n;
  for (int i = 0; i < n; ++i) {
    EXPECT_GE(t[i], kBounds.near + i * bin - 1e-5f) << i;
    EXPECT_LE(t[i], kBounds.near + (i + 1) * bin + 1e-5f) << i;
    EXPECT_GE(t[i], kBounds.near);
    EXPECT_LE(t[i], kBounds.far);
    if (i > 0) {
      EXPECT_LE(t[i - 1], t[i]);
    }
  }
  // δᵢ = tᵢ₊₁ − tᵢ, last δ = far − t_last: the intervals tile [t₀, far].
  for (int i = 0; i + 1 < n; ++i) EXPECT_EQ(delta[i], t[i + 1] - t[i]);
  EXPECT_EQ(delta[n - 1], kBounds.far - t[n - 1]);
}

TEST(NerfSampler, StratifiedIsDeterministicForASeed) {
  std::vector<float> a(32), b(32), c(32), delta(32);
  std::mt19937 rng_a(5), rng_b(5), rng_c(6);
  stratified_samples(kBounds, true, rng_a, a, delta);
  stratified_samples(kBounds, true, rng_b, b, delta);
  stratified_samples(kBounds, true, rng_c, c, delta);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
}

TEST(NerfSampler, StratifiedWithoutJitterGivesBinMidpointsAndLeavesTheRngAlone) {
  std::vector<float> t(4), delta(4);
  std::mt19937 rng(1), untouched(1);
  stratified_samples(kBounds, false, rng, t, delta);
  EXPECT_EQ(t, (std::vector<float>{2.5f, 3.5f, 4.5f, 5.5f}));
  EXPECT_EQ(delta, (std::vector<float>{1.0f, 1.0f, 1.0f, 0.5f}));
  EXPECT_EQ(rng(), untouched());
}

// Coarse samples at bin midpoints with one weight spike in bin `spike`.
struct SpikeRay {
  std::vector<float> t, delta, weights;
  SpikeRay(int n, int spike) : t(n), delta(n), weights(n, 0.0f) {
    std::mt19937 unused(0);
    stratified_samples(kBounds, false, unused, t, delta);
    weights[spike] = 0.8f;
  }
};

TEST(NerfSampler, HierarchicalSamplesConcentrateOnTheWeights) {
  const int n_coarse = 64, n_fine = 128, spike = 20;
  const SpikeRay coarse(n_coarse, spike);
  for (bool jitter : {true, false}) {
    std::mt19937 rng(9);
    std::vector<float> fine(n_fine), t(n_coarse + n_fine), delta(n_coarse + n_fine);
    hierarchical_samples(coarse.t, coarse.delta, coarse.weights, jitter, rng, fine, t, delta);
    const float lo = coarse.t[spike], hi = coarse.t[spike] + coarse.delta[spike];
    const auto in_spike = std::count_if(fine.begin(), fine.end(),
                                        [&](float x) { return x >= lo && x <= hi; });
    EXPECT_GE(in_spike, 0.9 * n_fine) << "jitter " << jitter;
    EXPECT_TRUE(std::is_sorted(fine.begin(), fine.end()));
    // Merged: all coarse and fine positions, sorted, with consistent lengths.
    EXPECT_TRUE(std::is_sorted(t.begin(), t.end()));
    std::vector<float> expected(coarse.t);
    expected.insert(expected.end(), fine.begin(), fine.end());
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(t, expected);
    for (std::size_t i = 0; i + 1 < t.size(); ++i) EXPECT_EQ(delta[i], t[i + 1] - t[i]);
    EXPECT_FLOAT_EQ(delta.back(), kBounds.far - t.back());
  }
}

TEST(NerfSampler, MergedIntervalsNeverSpanAGapBetweenCoarseIntervals) {
  // Coarse intervals [1, 1.5] and [3, 3.5] (the samples between them were in empty cells).
  const std::vector<float> coarse_t = {1.0f, 3.0f}, coarse_delta = {0.5f, 0.5f};
  const std::vector<float> fine = {1.25f, 3.0f, 3.25f};
  std::vector<float> t(5), delta(5);
  merge_samples(coarse_t, coarse_delta, fine, t, delta);
  EXPECT_EQ(t, (std::vector<float>{1.0f, 1.25f, 3.0f, 3.0f, 3.25f}));
  // 1.25 ends at its coarse interval's end (1.5), not at the next sample (3.0).
  EXPECT_EQ(delta, (std::vector<float>{0.25f, 0.25f, 0.0f, 0.25f, 0.25f}));
  // Without the gap (second interval starting at 1.5) the lengths reach the next sample.
  const std::vector<float> contiguous_t = {1.0f, 1.5f}, contiguous_delta = {0.5f, 0.5f};
  const std::vector<float> fine2 = {1.25f};
  std::vector<float> t2(3), delta2(3);
  merge_samples(contiguous_t, contiguous_delta, fine2, t2, delta2);
  EXPECT_EQ(delta2, (std::vector<float>{0.25f, 0.25f, 0.5f}));
}

TEST(NerfSampler, HierarchicalWithZeroWeightsGivesEveryIntervalTheSameShare) {
  // All weights zero: the ε alone gives every interval the same mass; deterministic u at
  // (j + 0.5)/16 then puts two samples in each of the 8 intervals, at 1/4 and 3/4 of it
  // (the last interval, far − t_last, is half as long as the others).
  std::vector<float> t(8), delta(8), weights(8, 0.0f), fine(16);
  std::mt19937 rng(0);
  stratified_samples(kBounds, false, rng, t, delta);
  importance_samples(t, delta, weights, false, rng, fine);
  for (int i = 0; i < 8; ++i) {
    EXPECT_NEAR(fine[2 * i], t[i] + 0.25f * delta[i], 1e-5f) << i;
    EXPECT_NEAR(fine[2 * i + 1], t[i] + 0.75f * delta[i], 1e-5f) << i;
  }
}

TEST(NerfSampler, HierarchicalIsDeterministicForASeed) {
  const SpikeRay coarse(16, 3);
  std::vector<float> a(40), b(40);
  std::mt19937 rng_a(2), rng_b(2);
  importance_samples(coarse.t, coarse.delta, coarse.weights, true, rng_a, a);
  importance_samples(coarse.t, coarse.delta, coarse.weights, true, rng_b, b);
  EXPECT_EQ(a, b);
}

TEST(NerfSampler, HierarchicalStaysInsideTheCoarseIntervals) {
  // Intervals with gaps (as after dropping samples in empty cells): nothing lands in a gap.
  const std::vector<float> t = {1.0f, 3.0f, 5.0f}, delta = {0.5f, 0.5f, 0.5f};
  const std::vector<float> weights = {0.2f, 0.5f, 0.3f};
  std::vector<float> fine(300);
  std::mt19937 rng(4);
  importance_samples(t, delta, weights, true, rng, fine);
  for (float x : fine) {
    const bool inside = (x >= 1.0f && x <= 1.5f) || (x >= 3.0f && x <= 3.5f) ||
                        (x >= 5.0f && x <= 5.5f);
    EXPECT_TRUE(inside) << x;
  }
  // Roughly in proportion to the weights: 60, 150, 90 expected.
  const auto middle =
      std::count_if(fine.begin(), fine.end(), [](float x) { return x >= 3.0f && x <= 3.5f; });
  EXPECT_NEAR(double(middle), 150.0, 3.0);  // stratified u: within a sample or two
}

TEST(NerfSampler, RejectsMismatchedSizes) {
  std::vector<float> t(4), delta(3), fine(2);
  std::mt19937 rng(0);
  EXPECT_THROW(stratified_samples(kBounds, true, rng, t, delta), ArgumentError);
  EXPECT_THROW(importance_samples({}, {}, {}, true, rng, fine), ArgumentError);
  std::vector<float> merged(5), merged_delta(5);
  EXPECT_THROW(merge_samples(t, delta, fine, merged, merged_delta), ArgumentError);
}

}  // namespace
}  // namespace splat
