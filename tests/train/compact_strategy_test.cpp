// The compact density strategy on hand-made statistics: the Gaussian cap holds, every row
// keeps its own Adam moments (or fresh ones) through growth, pruning and relocation, invisible
// Gaussians are pruned at the end of a window, and the resolution warm-up halves on schedule.
#include "splat/train/compact_strategy.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "splat/data/dataset.hpp"
#include "splat/train/density_strategy.hpp"
#include "splat/train/training_config.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

constexpr float kExtent = 1.0f;

// A model whose rows carry an identity tag in their last SH coefficient (copied by every row
// operation, untouched by splits), with Adam moments derived from the tag, so a test can tell
// whether each row's moments are its own.
struct Fixture {
  GaussianModel model;
  AdamState adam;
  std::mt19937 rng{3};

  explicit Fixture(std::size_t n) : model(test::random_model(int(n), 1, 7)) {
    adam.reset_like(model);
    adam.step = 10;
    for (std::size_t i = 0; i < n; ++i) {
      tag(model, i) = float(i + 1);
      model.opacity_logits[i] = logit(0.2f + 0.6f * float(i) / float(n));
      for (GaussianModel* moment : {&adam.first_moment, &adam.second_moment})
        for (float& v : row_values(*moment, i)) v = moment_for(float(i + 1));
    }
  }
  static float& tag(GaussianModel& m, std::size_t i) {
    const std::size_t width = std::size_t(m.sh_coefficients()) * 3;
    return m.sh[i * width + width - 1];
  }
  static float moment_for(float tag) { return 0.5f + tag; }
  static std::vector<std::reference_wrapper<float>> row_values(GaussianModel& m, std::size_t i) {
    std::vector<std::reference_wrapper<float>> out;
    for (int a = 0; a < 3; ++a) out.push_back(m.means[3 * i + a]);
    for (int a = 0; a < 3; ++a) out.push_back(m.log_scales[3 * i + a]);
    for (int a = 0; a < 4; ++a) out.push_back(m.quats[4 * i + a]);
    out.push_back(m.opacity_logits[i]);
    return out;
  }
  TrainingState state() { return {model, adam, rng, kExtent}; }

  // Every row's moments are zero (new or moved) or those of the row its tag names.
  void expect_moments_follow_rows() {
    ASSERT_EQ(adam.first_moment.size(), model.size());
    ASSERT_EQ(adam.second_moment.size(), model.size());
    for (std::size_t r = 0; r < model.size(); ++r) {
      const float expected = moment_for(tag(model, r));
      for (GaussianModel* moment : {&adam.first_moment, &adam.second_moment})
        for (float v : row_values(*moment, r))
          EXPECT_TRUE(v == 0.0f || v == expected) << "row " << r << " holds moment " << v
                                                  << ", its tag says " << expected;
    }
  }
};

// One iteration's statistics: every Gaussian visible with the given gradient norm and weight.
struct Stats {
  std::vector<float> grad, weight;
  std::vector<std::int32_t> radii;
  Stats(std::size_t n, float g, float w) : grad(n, g), weight(n, w), radii(n, 5) {}
  // One view's statistics, as a step without --batch passes them.
  std::array<BackwardStats, 1> view() const { return {BackwardStats{grad, radii, weight, 64, 64}}; }
};

CompactSettings growth_settings() {
  CompactSettings s;
  s.grow_from = 0;
  s.grow_interval = 10;
  s.grow_max_fraction = 1.0;
  s.grow_grad_threshold = 1e-3f;
  return s;
}

// Pruning alone: no growth, a window of 10 views, a weight threshold of `weight` pixels.
CompactSettings pruning_settings(float weight) {
  CompactSettings s;
  s.grow_from = 0;
  s.grow_until = 0;
  s.prune_window = 10;
  s.prune_weight = weight;
  return s;
}

// One step after the backward pass, on the given statistics and schedule iteration.
DensityStepReport step_once(CompactStrategy& strategy, Fixture& f, int iteration, const Stats& stats,
                            int schedule_iteration = 0) {
  GaussianModel grads = f.model;
  grads.set_zero();
  TrainingState state = f.state();
  state.schedule_iteration = schedule_iteration;
  return strategy.step_post_backward(iteration, false, state, grads, stats.view());
}

// Iterations first..last with every row's gradient norm `grad` and blending weight
// weight_of(row, iteration).
void run_iterations(CompactStrategy& strategy, Fixture& f, int first, int last, float grad,
                    const std::function<float(std::size_t, int)>& weight_of) {
  for (int it = first; it <= last; ++it) {
    Stats stats(f.model.size(), grad, 0.0f);
    for (std::size_t i = 0; i < stats.weight.size(); ++i) stats.weight[i] = weight_of(i, it);
    step_once(strategy, f, it, stats);
  }
}

void run_iterations(CompactStrategy& strategy, Fixture& f, int first, int last, float grad,
                    float weight) {
  run_iterations(strategy, f, first, last, grad, [weight](std::size_t, int) { return weight; });
}

TEST(CompactStrategy, GrowthNeverExceedsTheGaussianCap) {
  for (bool sampling : {false, true}) {
    Fixture f(100);
    CompactSettings s = growth_settings();
    s.grow_by_sampling = sampling;
    DensityControlSettings density;
    density.max_gaussians = 130;
    CompactStrategy strategy(s, density, 10, 0, f.model.size());
    for (int it = 1; it <= 50; ++it) {
      run_iterations(strategy, f, it, it, 1.0f, 100.0f);
      ASSERT_LE(f.model.size(), 130u) << "iteration " << it << (sampling ? " (sampling)" : "");
    }
    EXPECT_GT(f.model.size(), 100u) << "it grew at all";
  }
}

TEST(CompactStrategy, GrowthStepsAddAtMostTheirFractionAndOnlyAboveTheThreshold) {
  Fixture f(200);
  CompactSettings s = growth_settings();
  s.grow_max_fraction = 0.1;
  CompactStrategy strategy(s, {}, 10, 0, f.model.size());
  run_iterations(strategy, f, 1, 10, 0.5e-3f, 100.0f);  // below the threshold
  EXPECT_EQ(f.model.size(), 200u);
  run_iterations(strategy, f, 11, 20, 2e-3f, 100.0f);
  EXPECT_GT(f.model.size(), 200u);
  EXPECT_LE(f.model.size(), 220u);
}

TEST(CompactStrategy, AdamMomentsStayWithTheirRowsThroughGrowthPruningAndRelocation) {
  for (bool sampling : {false, true})
    for (bool relocate : {false, true}) {
      Fixture f(120);
      // A third of the rows transparent: pruned or relocated at the growth step.
      for (std::size_t i = 0; i < 120; i += 3) f.model.opacity_logits[i] = logit(0.001f);
      CompactSettings s = growth_settings();
      s.grow_by_sampling = sampling;
      s.relocate_dead = relocate;
      s.prune_weight = 50.0f;
      s.prune_window = 10;
      CompactStrategy strategy(s, {}, 10, 0, f.model.size());
      run_iterations(strategy, f, 1, 10, 2e-3f, 100.0f);
      f.expect_moments_follow_rows();
      const std::size_t after_growth = f.model.size();
      EXPECT_NE(after_growth, 120u);
      // A window in which half the rows make almost nothing visible: they are pruned.
      run_iterations(strategy, f, 11, 20, 0.0f,
                     [](std::size_t i, int) { return i % 2 == 0 ? 0.1f : 100.0f; });
      EXPECT_EQ(f.model.size(), after_growth - (after_growth + 1) / 2)
          << "sampling " << sampling << " relocate " << relocate;
      f.expect_moments_follow_rows();
    }
}

// Over a window of 10 views, even rows are drawn faintly in every view (1 pixel each: sum 10,
// peak 1) and odd rows strongly in one view only (6 pixels: sum 6, peak 6). The sum rule
// prunes the odd rows at a threshold of 8; the peak rule prunes the even ones at 3.
TEST(CompactStrategy, PruningComparesTheSummedOrThePeakBlendingWeight) {
  for (bool peak : {false, true}) {
    Fixture f(40);
    CompactSettings s = pruning_settings(peak ? 3.0f : 8.0f);
    s.prune_by_peak_weight = peak;
    CompactStrategy strategy(s, {}, 10, 0, f.model.size());
    run_iterations(strategy, f, 1, 10, 0.0f, [](std::size_t i, int it) {
      return i % 2 == 0 ? 1.0f : (it == 4 ? 6.0f : 0.0f);
    });
    ASSERT_EQ(f.model.size(), 20u) << (peak ? "peak" : "sum");
    for (std::size_t r = 0; r < 20; ++r) {
      const int original_row = int(Fixture::tag(f.model, r)) - 1;
      EXPECT_EQ(original_row % 2, peak ? 1 : 0) << (peak ? "peak" : "sum") << ": row " << r;
    }
  }
}

// A window of 10 views: rows 0-9 are drawn strongly in every view, rows 10-19 in one view only
// (a floater in front of one camera), rows 20-29 in two, rows 30-39 in every view but faintly.
// With a minimum share of 0.15 (1.5 views), the one-view rows go; the faint rows go by weight.
TEST(CompactStrategy, PruningRemovesWhatTooFewViewsDraw) {
  for (float share : {0.0f, 0.15f}) {
    Fixture f(40);
    CompactSettings s = pruning_settings(1.0f);
    s.prune_by_peak_weight = true;
    s.prune_min_view_share = share;
    CompactStrategy strategy(s, {}, 10, 0, f.model.size());
    run_iterations(strategy, f, 1, 10, 0.0f, [](std::size_t i, int it) {
      if (i < 10) return 2.0f;
      if (i < 20) return it == 3 ? 5.0f : 0.1f;
      if (i < 30) return it == 3 || it == 7 ? 5.0f : 0.1f;
      return 0.5f;
    });
    ASSERT_EQ(f.model.size(), share > 0 ? 20u : 30u) << "share " << share;
    for (std::size_t r = 0; r < f.model.size(); ++r) {
      const int original_row = int(Fixture::tag(f.model, r)) - 1;
      EXPECT_TRUE(original_row < 30 && (share == 0 || original_row < 10 || original_row >= 20))
          << "share " << share << ": row " << r << " was row " << original_row;
    }
    f.expect_moments_follow_rows();
  }
}

// One camera at the origin looking down +z whose points begin at depth 10: at the end of each
// window, the rows placed at depth 4 (in front of half of that) go, those at depth 8 stay, and
// without bounds (data without points) nothing goes.
TEST(CompactStrategy, PruningRemovesWhatSitsInFrontOfTheCamerasPoints) {
  Camera camera;
  camera.fx = camera.fy = 100;
  camera.cx = camera.cy = 50;
  camera.width = camera.height = 100;
  for (bool with_bounds : {false, true}) {
    Fixture f(20);
    for (std::size_t i = 0; i < 20; ++i) {
      f.model.means[3 * i] = 0.01f * float(i);
      f.model.means[3 * i + 1] = 0.0f;
      f.model.means[3 * i + 2] = i % 2 == 0 ? 4.0f : 8.0f;
    }
    CompactSettings s = pruning_settings(0.0f);
    s.prune_before_points = 0.5f;
    std::vector<CameraNearBound> bounds;
    if (with_bounds) bounds.push_back({camera, 10.0f});
    CompactStrategy strategy(s, {}, 10, 0, f.model.size(), bounds);
    run_iterations(strategy, f, 1, 9, 0.0f, 1.0f);
    ASSERT_EQ(f.model.size(), 20u) << "pruned before the window ended";
    run_iterations(strategy, f, 10, 10, 0.0f, 1.0f);
    ASSERT_EQ(f.model.size(), with_bounds ? 10u : 20u);
    for (std::size_t r = 0; r < f.model.size(); ++r)
      EXPECT_TRUE(!with_bounds || f.model.means[3 * r + 2] == 8.0f) << "row " << r;
    f.expect_moments_follow_rows();
    EXPECT_EQ(strategy.metrics().at("gaussians_pruned_before_points").get<std::size_t>(), with_bounds ? 10u : 0u);
  }
}

// Every row is drawn with a peak weight of 2 pixels (even rows) or 4 (odd rows). While the
// model may grow (to iteration 15) the threshold is 1 and nothing goes; the first window
// after growth applies the after-growth threshold of 3 and prunes the even rows.
TEST(CompactStrategy, PruningThresholdRisesOnceGrowthStops) {
  Fixture f(40);
  CompactSettings s;
  s.grow_from = 0;
  s.grow_until = 15;
  s.grow_grad_threshold = 1.0f;  // no growth: only pruning is under test
  s.prune_window = 10;
  s.prune_weight = 1.0f;
  s.prune_weight_after_growth = 3.0f;
  s.prune_by_peak_weight = true;
  CompactStrategy strategy(s, {}, 10, 0, f.model.size());
  const auto weight_of = [](std::size_t i, int) { return i % 2 == 0 ? 2.0f : 4.0f; };
  run_iterations(strategy, f, 1, 10, 0.0f, weight_of);
  ASSERT_EQ(f.model.size(), 40u) << "pruned while growing";
  run_iterations(strategy, f, 11, 20, 0.0f, weight_of);
  ASSERT_EQ(f.model.size(), 20u);
  for (std::size_t r = 0; r < 20; ++r)
    EXPECT_EQ((int(Fixture::tag(f.model, r)) - 1) % 2, 1) << "row " << r;
}

// A time budget running out moves the schedule on: at iteration 20 of a run whose budget is
// as far along as iteration 2,000, growth (until 1,000) has ended.
TEST(CompactStrategy, GrowthEndsWhenTheScheduleIterationPassesItsLimit) {
  for (int schedule_iteration : {0, 2000}) {
    Fixture f(100);
    CompactSettings s = growth_settings();
    s.grow_until = 1000;
    CompactStrategy strategy(s, {}, 10, 0, f.model.size());
    for (int it = 1; it <= 20; ++it)
      step_once(strategy, f, it, Stats(f.model.size(), 1.0f, 100.0f), schedule_iteration);
    if (schedule_iteration == 0)
      EXPECT_GT(f.model.size(), 100u);
    else
      EXPECT_EQ(f.model.size(), 100u);
  }
}

TEST(CompactStrategy, TheLastIterationOnlyGathersStatistics) {
  Fixture f(50);
  CompactStrategy strategy(growth_settings(), {}, 10, 0, f.model.size());
  GaussianModel grads = f.model;
  TrainingState state = f.state();
  const Stats stats(50, 1.0f, 0.0f);
  const DensityStepReport report = strategy.step_post_backward(10, true, state, grads, stats.view());
  EXPECT_FALSE(report.densified);
  EXPECT_EQ(f.model.size(), 50u);
}

TEST(CompactStrategy, RegularisersAddTheirGradients) {
  Fixture f(10);
  CompactSettings s;
  s.opacity_regularization = 0.5f;
  s.scale_regularization = 0.3f;
  s.grow_from = 1000;
  CompactStrategy strategy(s, {}, 10, 0, f.model.size());
  GaussianModel grads = f.model;
  grads.set_zero();
  TrainingState state = f.state();
  const Stats stats(10, 0.0f, 1.0f);
  strategy.step_post_backward(1, false, state, grads, stats.view());
  for (std::size_t i = 0; i < 10; ++i) {
    const float o = 1.0f / (1.0f + std::exp(-f.model.opacity_logits[i]));
    EXPECT_NEAR(grads.opacity_logits[i], 0.5f / 10 * o * (1 - o), 1e-7f);
    EXPECT_NEAR(grads.log_scales[3 * i], 0.3f / 30 * std::exp(f.model.log_scales[3 * i]), 1e-7f);
  }
}

TEST(CompactStrategy, OpacityDecayTakesItsShareInsideTheGrowthSpanOnly) {
  Fixture f(10);
  f.model.opacity_logits[0] = -100.0f;  // long transparent: must stay finite
  f.model.opacity_logits[1] = 30.0f;    // saturated: must come down, not stay at 1
  const GaussianModel before = f.model;
  CompactSettings s;
  s.opacity_decay = 0.01f;
  s.grow_from = 5;
  s.grow_until = 8;
  CompactStrategy strategy(s, {}, 10, 0, f.model.size());
  const auto opacity = [](float stored) { return 1.0 / (1.0 + std::exp(-double(stored))); };
  for (int it = 1; it <= 12; ++it) {
    TrainingState state = f.state();
    strategy.step_post_optimizer(it, state, 0.0f);
  }
  // Iterations 5..8 decay: four steps of × 0.99; everything else is untouched.
  for (std::size_t i = 0; i < 10; ++i) {
    ASSERT_TRUE(std::isfinite(f.model.opacity_logits[i])) << "row " << i;
    EXPECT_NEAR(opacity(f.model.opacity_logits[i]), std::pow(0.99, 4) * opacity(before.opacity_logits[i]),
                1e-4 * opacity(before.opacity_logits[i]))
        << "row " << i;
  }
  EXPECT_LT(f.model.opacity_logits[0], -100.0f);
  EXPECT_EQ(f.model.means, before.means);
  EXPECT_EQ(f.model.sh, before.sh);
}

// With opacity_decay_from the schedule is split: the resets run before it, the decay from it.
TEST(CompactStrategy, OpacityDecayTakesOverFromTheResetsAtItsStart) {
  Fixture f(10);
  CompactSettings s;
  s.grow_from = 0;
  s.grow_until = 100;
  s.prune_weight = 0.0f;
  s.opacity_reset_interval = 10;
  s.opacity_decay = 0.01f;
  s.opacity_decay_from = 45;
  CompactStrategy strategy(s, {}, 10, 0, f.model.size());
  std::vector<int> resets, decays;
  for (int it = 1; it <= 100; ++it) {
    if (step_once(strategy, f, it, Stats(f.model.size(), 0.0f, 1.0f)).opacity_reset) resets.push_back(it);
    const float before = f.model.opacity_logits[3];
    TrainingState state = f.state();
    strategy.step_post_optimizer(it, state, 0.0f);
    if (f.model.opacity_logits[3] != before) decays.push_back(it);
  }
  EXPECT_EQ(resets, (std::vector<int>{10, 20, 30, 40}));
  ASSERT_EQ(decays.size(), 56u);
  EXPECT_EQ(decays.front(), 45);
  EXPECT_EQ(decays.back(), 100);
}

// The preset decays opacities on a real capture (a point cloud) from half-way through growth;
// data without a point cloud keeps the resets alone.
TEST(CompactStrategy, ThePresetDecaysOpacityAndPrunesByViewShareOnlyWithAPointCloud) {
  const CompactSettings preset = splat_training_preset("compact").compact;
  ASSERT_GT(preset.opacity_decay, 0.0f);
  ASSERT_GT(preset.prune_min_view_share, 0.0f);
  EXPECT_EQ(preset.opacity_decay_from, preset.grow_until / 2);
  EXPECT_GT(preset.opacity_reset_interval, 0);
  Dataset capture;
  capture.points = PointCloud{};
  EXPECT_EQ(compact_settings_for(preset, capture).opacity_decay, preset.opacity_decay);
  EXPECT_EQ(compact_settings_for(preset, capture).prune_min_view_share, preset.prune_min_view_share);
  const Dataset synthetic;
  EXPECT_EQ(compact_settings_for(preset, synthetic).opacity_decay, 0.0f);
  EXPECT_EQ(compact_settings_for(preset, synthetic).prune_min_view_share, 0.0f);
  EXPECT_EQ(compact_settings_for(preset, synthetic).opacity_reset_interval, preset.opacity_reset_interval);
  CompactSettings everywhere = preset;  // compact_real_capture_only false: as configured
  everywhere.real_capture_only = false;
  EXPECT_EQ(compact_settings_for(everywhere, synthetic).opacity_decay, preset.opacity_decay);
  EXPECT_EQ(compact_settings_for(everywhere, synthetic).prune_min_view_share, preset.prune_min_view_share);
}

}  // namespace
}  // namespace splat
