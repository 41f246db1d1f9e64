#include "splat/optim/density_control.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "splat/core/error.hpp"
#include "splat/raster/projection_math.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

constexpr float kExtent = 1.0f;
constexpr float kBigGrad = 1e-3f;    // well above the 2e-4 threshold
constexpr float kSmallGrad = 1e-5f;  // well below it
const float kSmallLogScale = std::log(0.005f);  // below percent_dense · extent = 0.01: clone
const float kLargeLogScale = std::log(0.05f);   // above it: split

// A model, Adam moments that are non-zero and distinct per row, and density control over
// them. Opacity logits are distinct per row (2 + i/100), so rows can be recognised after
// they move.
struct Fixture {
  GaussianModel model;
  AdamState adam;
  DensityControl control;

  Fixture(std::size_t n, const DensityControlSettings& settings = {}, unsigned seed = 1)
      : model(test::random_model(int(n), 1, seed)), control(settings, n) {
    adam.first_moment = test::random_model(int(n), 1, seed + 100);
    adam.second_moment = test::random_model(int(n), 1, seed + 200);
    adam.step = 7;
    for (std::size_t i = 0; i < n; ++i) {
      model.opacity_logits[i] = 2.0f + 0.01f * float(i);
      for (int a = 0; a < 3; ++a) model.log_scales[3 * i + a] = kSmallLogScale;
    }
  }
  void set_grad(std::size_t i, float mean_grad) {
    control.stats().grad_accum[i] = 2.0f * mean_grad;
    control.stats().denom[i] = 2.0f;
  }
  void set_log_scales(std::size_t i, float a, float b, float c) {
    model.log_scales[3 * i] = a;
    model.log_scales[3 * i + 1] = b;
    model.log_scales[3 * i + 2] = c;
  }
  DensityControlReport densify(std::mt19937& rng, std::optional<float> size = std::nullopt) {
    return control.densify_and_prune(model, adam, kExtent, size, rng);
  }
  // Row of the Gaussian whose opacity logit identifies original row `original`.
  std::vector<std::size_t> rows_of(std::size_t original) const {
    std::vector<std::size_t> rows;
    for (std::size_t i = 0; i < model.size(); ++i)
      if (model.opacity_logits[i] == 2.0f + 0.01f * float(original)) rows.push_back(i);
    return rows;
  }
};

std::vector<float> row_values(const GaussianModel& m, std::size_t row) {
  std::vector<float> out;
  auto take = [&](const std::vector<float>& array, std::size_t width) {
    for (std::size_t j = 0; j < width; ++j) out.push_back(array[row * width + j]);
  };
  take(m.means, 3);
  take(m.log_scales, 3);
  take(m.quats, 4);
  take(m.opacity_logits, 1);
  take(m.sh, std::size_t(m.sh_coefficients()) * 3);
  return out;
}

bool row_is_zero(const GaussianModel& m, std::size_t row) {
  for (float x : row_values(m, row))
    if (x != 0.0f) return false;
  return true;
}

TEST(DensityControl, ClonesSmallGaussianWithLargeGradient) {
  Fixture f(4);
  f.set_grad(1, kBigGrad);
  f.set_grad(2, kSmallGrad);
  const GaussianModel before = f.model;
  const AdamState adam_before = f.adam;
  std::mt19937 rng(1);
  const DensityControlReport report = f.densify(rng);
  EXPECT_TRUE(report.densified);
  EXPECT_EQ(report.cloned, 1u);
  EXPECT_EQ(report.split, 0u);
  EXPECT_EQ(report.pruned, 0u);
  ASSERT_EQ(report.count_after, 5u);
  ASSERT_EQ(f.model.size(), 5u);
  // Originals in place with their moments; the copy appended, identical, with zero moments.
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(row_values(f.model, i), row_values(before, i));
    EXPECT_EQ(row_values(f.adam.first_moment, i), row_values(adam_before.first_moment, i));
    EXPECT_EQ(row_values(f.adam.second_moment, i), row_values(adam_before.second_moment, i));
  }
  EXPECT_EQ(row_values(f.model, 4), row_values(before, 1));
  EXPECT_TRUE(row_is_zero(f.adam.first_moment, 4));
  EXPECT_TRUE(row_is_zero(f.adam.second_moment, 4));
  EXPECT_EQ(f.adam.step, 7);
}

TEST(DensityControl, SplitsLargeGaussianIntoTwoSmallerOnes) {
  Fixture f(3);
  f.set_log_scales(1, std::log(0.3f), std::log(0.05f), std::log(0.1f));
  f.set_grad(1, kBigGrad);
  const GaussianModel before = f.model;
  const AdamState adam_before = f.adam;
  std::mt19937 rng(2);
  const DensityControlReport report = f.densify(rng);
  EXPECT_EQ(report.split, 1u);
  EXPECT_EQ(report.cloned, 0u);
  ASSERT_EQ(f.model.size(), 4u);
  // Survivors first, in order, with their moments; the original is gone.
  EXPECT_EQ(row_values(f.model, 0), row_values(before, 0));
  EXPECT_EQ(row_values(f.model, 1), row_values(before, 2));
  EXPECT_EQ(row_values(f.adam.first_moment, 1), row_values(adam_before.first_moment, 2));
  EXPECT_EQ(row_values(f.adam.second_moment, 1), row_values(adam_before.second_moment, 2));
  const Mat3<float> rotation = quat_to_rotmat(
      Vec4<float>(before.quats[4], before.quats[5], before.quats[6], before.quats[7]));
  for (std::size_t r = 2; r < 4; ++r) {
    SCOPED_TRACE(testing::Message() << "offspring row " << r);
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(std::exp(f.model.log_scales[3 * r + a]),
                  std::exp(before.log_scales[3 + a]) / 1.6f, 1e-6);
    // Offset from the parent in the parent's frame, in units of its scale: a standard normal.
    Vec3<float> offset;
    for (int a = 0; a < 3; ++a) offset[a] = f.model.means[3 * r + a] - before.means[3 + a];
    const Vec3<float> local = glm::transpose(rotation) * offset;
    for (int a = 0; a < 3; ++a)
      EXPECT_LT(std::abs(local[a] / std::exp(before.log_scales[3 + a])), 5.0f);
    for (int j = 0; j < 4; ++j) EXPECT_EQ(f.model.quats[4 * r + j], before.quats[4 + j]);
    EXPECT_EQ(f.model.opacity_logits[r], before.opacity_logits[1]);
    for (std::size_t j = 0; j < 12; ++j) EXPECT_EQ(f.model.sh[12 * r + j], before.sh[12 + j]);
    EXPECT_TRUE(row_is_zero(f.adam.first_moment, r));
    EXPECT_TRUE(row_is_zero(f.adam.second_moment, r));
  }
  EXPECT_NE(f.model.means[6], f.model.means[9]);  // two different samples
}

TEST(DensityControl, SplitSamplesFollowTheRotatedScaledNormal) {
  // Many splits of rotated anisotropic Gaussians: mapped back into each parent's frame and
  // divided by its scale, the offsets are standard normal on every axis. A sample rotated
  // the wrong way (Rᵀ instead of R) or scaled on the wrong axis fails the variance check.
  constexpr std::size_t kCount = 4000;
  Fixture f(kCount);
  for (std::size_t i = 0; i < kCount; ++i) {
    f.set_log_scales(i, std::log(0.4f), std::log(0.02f), std::log(0.1f));
    f.set_grad(i, kBigGrad);
  }
  const GaussianModel before = f.model;
  std::mt19937 rng(3);
  f.densify(rng);
  ASSERT_EQ(f.model.size(), 2 * kCount);
  double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
  for (std::size_t r = 0; r < 2 * kCount; ++r) {
    const std::size_t parent = r % kCount;  // all first samples, then all second samples
    ASSERT_EQ(f.model.opacity_logits[r], before.opacity_logits[parent]);
    const float* q = &before.quats[4 * parent];
    const Mat3<float> rotation = quat_to_rotmat(Vec4<float>(q[0], q[1], q[2], q[3]));
    Vec3<float> offset;
    for (int a = 0; a < 3; ++a) offset[a] = f.model.means[3 * r + a] - before.means[3 * parent + a];
    const Vec3<float> local = glm::transpose(rotation) * offset;
    for (int a = 0; a < 3; ++a) {
      const double z = local[a] / std::exp(before.log_scales[3 * parent + a]);
      sum[a] += z;
      sum2[a] += z * z;
    }
  }
  for (int a = 0; a < 3; ++a) {
    const double mean = sum[a] / (2 * kCount), var = sum2[a] / (2 * kCount) - mean * mean;
    EXPECT_NEAR(mean, 0.0, 0.05) << "axis " << a;
    EXPECT_NEAR(var, 1.0, 0.06) << "axis " << a;
  }
}

TEST(DensityControl, PrunesTransparentGaussiansKeepingMomentsAligned) {
  Fixture f(5);
  f.model.opacity_logits[1] = logit(0.004f);
  f.model.opacity_logits[3] = logit(0.0049f);
  f.model.opacity_logits[4] = logit(0.0052f);
  const AdamState adam_before = f.adam;
  const GaussianModel before = f.model;
  std::mt19937 rng(4);
  const DensityControlReport report = f.densify(rng);
  EXPECT_EQ(report.pruned, 2u);
  ASSERT_EQ(f.model.size(), 3u);
  const std::size_t survivors[] = {0, 2, 4};
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(row_values(f.model, i), row_values(before, survivors[i]));
    EXPECT_EQ(row_values(f.adam.first_moment, i),
              row_values(adam_before.first_moment, survivors[i]));
    EXPECT_EQ(row_values(f.adam.second_moment, i),
              row_values(adam_before.second_moment, survivors[i]));
  }
  EXPECT_EQ(f.control.stats().size(), 3u);
}

TEST(DensityControl, CloneAndSplitThenPruneInOfficialRowOrder) {
  // Row order after one densification, as the official code leaves it: untouched originals,
  // then clones, then first samples, then second samples.
  Fixture f(4);
  f.set_grad(0, kBigGrad);  // clone
  f.set_log_scales(2, kLargeLogScale, kLargeLogScale, kLargeLogScale);
  f.set_grad(2, kBigGrad);  // split
  f.set_log_scales(3, kLargeLogScale, kLargeLogScale, kLargeLogScale);
  f.set_grad(3, kBigGrad);  // split
  std::mt19937 rng(5);
  const DensityControlReport report = f.densify(rng);
  EXPECT_EQ(report.cloned, 1u);
  EXPECT_EQ(report.split, 2u);
  ASSERT_EQ(f.model.size(), 4u + 1 + 2);
  const std::size_t expected_origin[] = {0, 1, 0, 2, 3, 2, 3};
  for (std::size_t r = 0; r < f.model.size(); ++r)
    EXPECT_EQ(f.model.opacity_logits[r], 2.0f + 0.01f * float(expected_origin[r])) << r;
}

TEST(DensityControl, SizePruningOnlyAfterTheFirstReset) {
  DensityControlSettings settings;
  Fixture f(3, settings);
  // Too large in the world (> 0.1 · extent) but with no gradient: never split.
  f.set_log_scales(1, std::log(0.15f), std::log(0.01f), std::log(0.01f));
  const std::vector<float> norms(3, 0.0f);
  const std::vector<std::int32_t> radii = {3, 30, 3};  // 30 px > 20 px as well
  std::mt19937 rng(6);
  DensityControlReport report =
      f.control.step(settings.opacity_reset_interval - 100, f.model, f.adam, norms, radii,
                     kExtent, rng);
  EXPECT_TRUE(report.densified);
  EXPECT_EQ(report.pruned, 0u);
  ASSERT_EQ(f.model.size(), 3u);
  report = f.control.step(settings.opacity_reset_interval + 100, f.model, f.adam, norms, radii,
                          kExtent, rng);
  EXPECT_TRUE(report.densified);
  EXPECT_EQ(report.pruned, 1u);
  ASSERT_EQ(f.model.size(), 2u);
  EXPECT_TRUE(f.rows_of(1).empty());
}

TEST(DensityControl, ScreenSizePruningIsOffAsInTheOfficialCodeUnlessAskedFor) {
  for (bool by_screen : {false, true}) {
    SCOPED_TRACE(by_screen ? "screen-size pruning on" : "official (off)");
    DensityControlSettings settings;
    settings.prune_by_screen_size = by_screen;
    Fixture f(3, settings);
    f.control.add_stats(std::vector<float>(3, 0.0f), std::vector<std::int32_t>{5, 25, 20});
    std::mt19937 rng(7);
    const DensityControlReport report = f.densify(rng, settings.max_screen_size);
    EXPECT_EQ(report.pruned, by_screen ? 1u : 0u);
    EXPECT_EQ(f.rows_of(1).empty(), by_screen);
    EXPECT_EQ(f.rows_of(2).size(), 1u);  // exactly at the limit: kept
  }
}

TEST(DensityControl, ScreenSizePruningSeesTheRadiiOfCopies) {
  DensityControlSettings settings;
  settings.prune_by_screen_size = true;
  Fixture f(2, settings);
  f.control.add_stats(std::vector<float>{kBigGrad, 0.0f}, std::vector<std::int32_t>{25, 5});
  std::mt19937 rng(8);
  const DensityControlReport report = f.densify(rng, settings.max_screen_size);
  EXPECT_EQ(report.cloned, 1u);
  EXPECT_EQ(report.pruned, 2u);  // the original and its clone
  EXPECT_EQ(f.model.size(), 1u);
}

TEST(DensityControl, AddStatsCountsOnlyVisibleGaussians) {
  Fixture f(3);
  f.control.add_stats(std::vector<float>{0.5f, 0.25f, 0.125f},
                      std::vector<std::int32_t>{4, 0, 7});
  f.control.add_stats(std::vector<float>{0.25f, 1.0f, 0.0f},
                      std::vector<std::int32_t>{9, 0, 2});
  const DensificationStats& s = f.control.stats();
  EXPECT_EQ(s.grad_accum, (std::vector<float>{0.75f, 0.0f, 0.125f}));
  EXPECT_EQ(s.denom, (std::vector<float>{2.0f, 0.0f, 2.0f}));
  EXPECT_EQ(s.max_radii, (std::vector<float>{9.0f, 0.0f, 7.0f}));
  EXPECT_THROW(f.control.add_stats(std::vector<float>(2), std::vector<std::int32_t>(3)),
               ArgumentError);
}

TEST(DensityControl, StatsAreZeroAfterDensification) {
  Fixture f(6);
  f.control.add_stats(std::vector<float>(6, kBigGrad), std::vector<std::int32_t>(6, 3));
  std::mt19937 rng(9);
  f.densify(rng);
  const DensificationStats& s = f.control.stats();
  ASSERT_EQ(s.size(), f.model.size());
  ASSERT_EQ(f.model.size(), 12u);
  for (std::size_t i = 0; i < s.size(); ++i) {
    EXPECT_EQ(s.grad_accum[i], 0.0f);
    EXPECT_EQ(s.denom[i], 0.0f);
    EXPECT_EQ(s.max_radii[i], 0.0f);
  }
}

TEST(DensityControl, ResetOpacityCapsAndZeroesOpacityMoments) {
  Fixture f(3);
  f.model.opacity_logits = {logit(0.5f), logit(0.004f), logit(0.01f)};
  const AdamState adam_before = f.adam;
  const GaussianModel before = f.model;
  reset_opacity(f.model, f.adam, 0.01f);
  EXPECT_NEAR(sigmoid(f.model.opacity_logits[0]), 0.01f, 1e-7);
  EXPECT_NEAR(sigmoid(f.model.opacity_logits[1]), 0.004f, 1e-7);  // below the cap: kept
  EXPECT_NEAR(sigmoid(f.model.opacity_logits[2]), 0.01f, 1e-7);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(f.adam.first_moment.opacity_logits[i], 0.0f);
    EXPECT_EQ(f.adam.second_moment.opacity_logits[i], 0.0f);
  }
  EXPECT_EQ(f.adam.first_moment.means, adam_before.first_moment.means);
  EXPECT_EQ(f.adam.second_moment.sh, adam_before.second_moment.sh);
  EXPECT_EQ(f.model.means, before.means);
  EXPECT_EQ(f.adam.step, adam_before.step);
}

TEST(DensityControl, BudgetPrefersTheLargestGradients) {
  // Ten candidates (even rows clone, odd rows split), gradients increasing with the row,
  // and room for four more Gaussians.
  DensityControlSettings settings;
  settings.max_gaussians = 14;
  Fixture f(10, settings);
  for (std::size_t i = 0; i < 10; ++i) {
    if (i % 2) f.set_log_scales(i, kLargeLogScale, kLargeLogScale, kLargeLogScale);
    f.set_grad(i, kBigGrad * float(1 + i));
  }
  std::mt19937 rng(10);
  const DensityControlReport report = f.densify(rng);
  EXPECT_EQ(report.over_budget, 6u);
  EXPECT_EQ(report.cloned, 2u);  // rows 6 and 8
  EXPECT_EQ(report.split, 2u);   // rows 7 and 9
  EXPECT_EQ(f.model.size(), 14u);
  for (std::size_t i = 0; i < 10; ++i)
    EXPECT_EQ(f.rows_of(i).size(), i >= 6 ? 2u : 1u) << "original row " << i;
  // Survivors (8), clones of 6 and 8, first samples of 7 and 9, second samples.
  EXPECT_EQ(f.rows_of(7), (std::vector<std::size_t>{10, 12}));
  EXPECT_EQ(f.rows_of(9), (std::vector<std::size_t>{11, 13}));
}

TEST(DensityControl, BudgetBreaksTiesByIndexAndNeverGrowsAFullModel) {
  DensityControlSettings settings;
  settings.max_gaussians = 7;
  Fixture f(5, settings);
  for (std::size_t i = 0; i < 5; ++i) f.set_grad(i, kBigGrad);
  std::mt19937 rng(11);
  DensityControlReport report = f.densify(rng);
  EXPECT_EQ(report.cloned, 2u);
  EXPECT_EQ(f.rows_of(0).size(), 2u);
  EXPECT_EQ(f.rows_of(1).size(), 2u);
  EXPECT_EQ(f.rows_of(2).size(), 1u);

  for (std::size_t i = 0; i < 7; ++i) f.set_grad(i, kBigGrad);
  report = f.densify(rng);  // already at the budget
  EXPECT_EQ(report.cloned + report.split, 0u);
  EXPECT_EQ(report.over_budget, 7u);
  EXPECT_EQ(f.model.size(), 7u);
}

TEST(DensityControl, BudgetIsNeverExceededOverManyRounds) {
  DensityControlSettings settings;
  settings.max_gaussians = 3000;
  Fixture f(1000, settings, 12);
  std::mt19937 rng(12), stats_rng(13);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int round = 0; round < 8; ++round) {
    const std::size_t n = f.model.size();
    for (std::size_t i = 0; i < n; ++i) {
      f.model.log_scales[3 * i] = std::log(0.001f + 0.05f * u(stats_rng));
      f.set_grad(i, 1e-3f * u(stats_rng));
    }
    const DensityControlReport report = f.densify(rng);
    EXPECT_LE(f.model.size(), settings.max_gaussians) << "round " << round;
    EXPECT_EQ(report.count_after, f.model.size());
  }
  EXPECT_GE(f.model.size(), 2900u);  // it does fill up
}

TEST(DensityControl, DeterministicForASeedAndAnyThreadCount) {
  auto run = [](unsigned seed, int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    Fixture f(500, {}, 14);
    std::mt19937 stats_rng(15);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (std::size_t i = 0; i < 500; ++i) {
      f.model.log_scales[3 * i + 1] = std::log(0.001f + 0.05f * u(stats_rng));
      f.set_grad(i, 5e-4f * u(stats_rng));
    }
    std::mt19937 rng(seed);
    f.densify(rng, 20.0f);
    return f;
  };
  const Fixture a = run(1, 1), b = run(1, 4), c = run(2, 2);
  EXPECT_GT(a.model.size(), 500u);
  EXPECT_EQ(a.model.means, b.model.means);
  EXPECT_EQ(a.model.log_scales, b.model.log_scales);
  EXPECT_EQ(a.model.sh, b.model.sh);
  EXPECT_EQ(a.adam.first_moment.means, b.adam.first_moment.means);
  EXPECT_EQ(a.model.size(), c.model.size());
  EXPECT_NE(a.model.means, c.model.means);  // the seed drives the split samples
}

TEST(DensityControl, FollowsTheOfficialIterationSchedule) {
  for (bool white : {false, true}) {
    SCOPED_TRACE(white ? "white background" : "black background");
    DensityControlSettings settings;
    settings.white_background = white;
    Fixture f(4, settings);
    const std::vector<float> norms(4, 0.0f);
    const std::vector<std::int32_t> radii(4, 2);
    std::mt19937 rng(16);
    std::vector<int> densified, resets;
    for (int it = 1; it <= 16000; ++it) {
      const DensityControlReport report =
          f.control.step(it, f.model, f.adam, norms, radii, kExtent, rng);
      if (report.densified) densified.push_back(it);
      if (report.opacity_reset) resets.push_back(it);
      EXPECT_EQ(report.count_after, 4u);
    }
    std::vector<int> expected_densified;
    for (int it = 600; it < 15000; it += 100) expected_densified.push_back(it);
    EXPECT_EQ(densified, expected_densified);
    std::vector<int> expected_resets = {3000, 6000, 9000, 12000};
    if (white) expected_resets.insert(expected_resets.begin(), 500);
    EXPECT_EQ(resets, expected_resets);
  }
}

// The run's last iteration: statistics as usual, but no densification and no reset, even
// on an iteration that would do both.
TEST(DensityControl, StatsOnlyStepChangesNothing) {
  DensityControlSettings settings;
  Fixture f(2, settings);
  std::mt19937 rng(18);
  const std::vector<float> norms = {kBigGrad, kBigGrad};
  const std::vector<std::int32_t> radii = {3, 3};
  const GaussianModel before = f.model;
  const int both = 3000;  // a densification and an opacity reset
  const DensityControlReport report =
      f.control.step(both, f.model, f.adam, norms, radii, kExtent, rng, /*stats_only=*/true);
  EXPECT_FALSE(report.densified);
  EXPECT_FALSE(report.opacity_reset);
  EXPECT_EQ(report.count_after, 2u);
  EXPECT_EQ(f.model.opacity_logits, before.opacity_logits);
  EXPECT_EQ(f.control.stats().denom[0], 1.0f);
  // The same step without the flag does densify (the case above is not vacuous).
  EXPECT_TRUE(f.control.step(both, f.model, f.adam, norms, radii, kExtent, rng).densified);
}

TEST(DensityControl, GathersStatsOnlyBeforeDensifyUntil) {
  DensityControlSettings settings;
  Fixture f(2, settings);
  std::mt19937 rng(17);
  const std::vector<float> norms = {kBigGrad, kBigGrad};
  const std::vector<std::int32_t> radii = {3, 3};
  f.control.step(settings.densify_until_iter - 1, f.model, f.adam, norms, radii, kExtent, rng);
  EXPECT_EQ(f.control.stats().denom[0], 1.0f);
  f.control.step(settings.densify_until_iter, f.model, f.adam, norms, radii, kExtent, rng);
  f.control.step(settings.densify_until_iter + 100, f.model, f.adam, norms, radii, kExtent,
                 rng);
  EXPECT_EQ(f.control.stats().denom[0], 1.0f);
  EXPECT_EQ(f.model.size(), 2u);
}

TEST(DensityControl, RejectsMismatchedState) {
  Fixture f(3);
  std::mt19937 rng(18);
  AdamState wrong;
  wrong.reset_like(test::random_model(2, 1, 1));
  EXPECT_THROW(f.control.densify_and_prune(f.model, wrong, kExtent, std::nullopt, rng),
               ArgumentError);
  EXPECT_THROW(reset_opacity(f.model, wrong, 0.01f), ArgumentError);
  GaussianModel bigger = test::random_model(4, 1, 2);
  AdamState fitting;
  fitting.reset_like(bigger);
  EXPECT_THROW(f.control.densify_and_prune(bigger, fitting, kExtent, std::nullopt, rng),
               ArgumentError);
  DensityControlSettings bad;
  bad.split_count = 0;
  EXPECT_THROW(DensityControl(bad, 3), ArgumentError);
}

}  // namespace
}  // namespace splat
