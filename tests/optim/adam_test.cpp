#include "splat/optim/adam.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "splat/core/error.hpp"
#include "splat/core/simd.hpp"
#include "splat/optim/lr_schedule.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

// Group learning rates far apart, so an element stepped with the wrong group's rate shows.
GroupLearningRates distinct_rates() {
  GroupLearningRates lr;
  lr.means = 0.01f;
  lr.sh_dc = 0.02f;
  lr.sh_rest = 0.003f;
  lr.opacity = 0.05f;
  lr.scales = 0.007f;
  lr.rotations = 0.001f;
  return lr;
}

// One element of the optimiser, in double, straight from the formulas.
struct ReferenceAdam {
  double p, m = 0, v = 0;
  void step(double g, double lr, int t) {
    const double b1 = 0.9, b2 = 0.999, eps = 1e-15;
    m = b1 * m + (1 - b1) * g;
    v = b2 * v + (1 - b2) * g * g;
    p -= lr / (1 - std::pow(b1, t)) * m / (std::sqrt(v) / std::sqrt(1 - std::pow(b2, t)) + eps);
  }
};

// The model's elements, each with the learning rate of its group, in one flat list.
struct Element {
  float* param;
  float* grad;
  float* m;
  float* v;
  float lr;
};

std::vector<Element> elements(GaussianModel& p, GaussianModel& g, AdamState& s,
                              const GroupLearningRates& lr) {
  std::vector<Element> out;
  auto add = [&](std::vector<float>& pa, std::vector<float>& ga, std::vector<float>& ma,
                 std::vector<float>& va, std::size_t i, float rate) {
    out.push_back({&pa[i], &ga[i], &ma[i], &va[i], rate});
  };
  GaussianModel &m = s.first_moment, &v = s.second_moment;
  for (std::size_t i = 0; i < p.means.size(); ++i) add(p.means, g.means, m.means, v.means, i, lr.means);
  for (std::size_t i = 0; i < p.log_scales.size(); ++i)
    add(p.log_scales, g.log_scales, m.log_scales, v.log_scales, i, lr.scales);
  for (std::size_t i = 0; i < p.quats.size(); ++i) add(p.quats, g.quats, m.quats, v.quats, i, lr.rotations);
  for (std::size_t i = 0; i < p.opacity_logits.size(); ++i)
    add(p.opacity_logits, g.opacity_logits, m.opacity_logits, v.opacity_logits, i, lr.opacity);
  const std::size_t row = std::size_t(p.sh_coefficients()) * 3;
  for (std::size_t i = 0; i < p.sh.size(); ++i)
    add(p.sh, g.sh, m.sh, v.sh, i, i % row < 3 ? lr.sh_dc : lr.sh_rest);
  return out;
}

TEST(Adam, MatchesHandComputedStepsPerGroup) {
  GaussianModel params = test::random_model(1, 1, 3);
  GaussianModel grads = params;
  AdamState state;
  state.reset_like(params);
  const GroupLearningRates lr = distinct_rates();
  std::vector<Element> el = elements(params, grads, state, lr);
  ASSERT_EQ(el.size(), 23u);  // 3 + 3 + 4 + 1 + 4·3

  std::vector<ReferenceAdam> ref;
  for (const Element& e : el) ref.push_back({*e.param});
  std::mt19937 rng(4);
  std::normal_distribution<float> normal(0.0f, 0.5f);
  for (int t = 1; t <= 4; ++t) {
    for (std::size_t i = 0; i < el.size(); ++i) {
      *el[i].grad = normal(rng);
      ref[i].step(*el[i].grad, el[i].lr, t);
    }
    adam_step(params, grads, state, lr);
    EXPECT_EQ(state.step, t);
    for (std::size_t i = 0; i < el.size(); ++i) {
      SCOPED_TRACE(testing::Message() << "element " << i << " step " << t);
      EXPECT_NEAR(*el[i].param, ref[i].p, 1e-6 + 1e-6 * std::abs(ref[i].p));
      EXPECT_NEAR(*el[i].m, ref[i].m, 1e-6 * std::abs(ref[i].m) + 1e-12);
      EXPECT_NEAR(*el[i].v, ref[i].v, 1e-6 * std::abs(ref[i].v) + 1e-15);
    }
  }
}

TEST(Adam, FirstStepMovesEachElementByItsGroupRate) {
  // After one step m̂/sqrt(v̂) = sign(g): the displacement is the group's learning rate, so
  // DC (k = 0) and the higher bands must move by different amounts.
  GaussianModel params = test::random_model(1, 3, 7);
  const GaussianModel before = params;
  GaussianModel grads = params;
  grads.set_zero();
  for (float& g : grads.sh) g = -1.0f;
  grads.opacity_logits[0] = 2.0f;
  AdamState state;
  state.reset_like(params);
  const GroupLearningRates lr = distinct_rates();
  adam_step(params, grads, state, lr);
  for (std::size_t i = 0; i < params.sh.size(); ++i) {
    const float expected = i < 3 ? lr.sh_dc : lr.sh_rest;
    EXPECT_NEAR(params.sh[i] - before.sh[i], expected, 1e-6) << "SH float " << i;
  }
  EXPECT_NEAR(params.opacity_logits[0] - before.opacity_logits[0], -lr.opacity, 1e-6);
}

TEST(Adam, ZeroGradientStillMovesByMomentum) {
  GaussianModel params = test::random_model(1, 0, 9);
  GaussianModel grads = params;
  AdamState state;
  state.reset_like(params);
  const GroupLearningRates lr = distinct_rates();
  ReferenceAdam ref{params.means[0]};
  grads.means[0] = 0.3f;
  ref.step(0.3, lr.means, 1);
  adam_step(params, grads, state, lr);
  grads.set_zero();
  const float before = params.means[0];
  ref.step(0.0, lr.means, 2);
  adam_step(params, grads, state, lr);
  EXPECT_LT(params.means[0], before);  // keeps going the way the earlier gradient pushed
  EXPECT_NEAR(params.means[0], ref.p, 1e-6);
}

TEST(Adam, MaskedGroupKeepsParametersAndMoments) {
  GaussianModel params = test::random_model(3, 1, 10);
  GaussianModel grads = test::random_model(3, 1, 11);
  AdamState state;
  state.reset_like(params);
  adam_step(params, grads, state, distinct_rates());
  const GaussianModel before = params;
  const AdamState state_before = state;
  AdamGroupMask mask;
  mask.opacity = false;
  adam_step(params, grads, state, distinct_rates(), {}, mask);
  EXPECT_EQ(params.opacity_logits, before.opacity_logits);
  EXPECT_EQ(state.first_moment.opacity_logits, state_before.first_moment.opacity_logits);
  EXPECT_EQ(state.second_moment.opacity_logits, state_before.second_moment.opacity_logits);
  EXPECT_NE(params.means, before.means);
  EXPECT_EQ(state.step, 2);
}

TEST(Adam, BothShGroupsTogetherStepBitForBitAsEachAlone) {
  // With both SH groups active the rows are stepped in one loop over their columns; with one
  // masked, each run of columns in a loop of its own. Every element must come out the same.
  const GaussianModel start = test::random_model(1001, 3, 31);
  const GaussianModel grads = test::random_model(1001, 3, 32);
  auto run = [&](bool dc, bool rest) {
    GaussianModel params = start;
    AdamState state;
    state.reset_like(params);
    AdamGroupMask mask;
    mask.sh_dc = dc;
    mask.sh_rest = rest;
    for (int i = 0; i < 3; ++i) adam_step(params, grads, state, distinct_rates(), {}, mask);
    return std::pair{params, state};
  };
  const auto [both, both_state] = run(true, true);
  const auto [dc, dc_state] = run(true, false);
  const auto [rest, rest_state] = run(false, true);
  const std::size_t row = std::size_t(start.sh_coefficients()) * 3;
  int mismatches = 0;
  for (std::size_t i = 0; i < start.sh.size(); ++i) {
    const bool is_dc = i % row < 3;
    const GaussianModel& alone = is_dc ? dc : rest;
    const AdamState& alone_state = is_dc ? dc_state : rest_state;
    mismatches += both.sh[i] != alone.sh[i] || both_state.first_moment.sh[i] != alone_state.first_moment.sh[i] ||
                  both_state.second_moment.sh[i] != alone_state.second_moment.sh[i];
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_NE(both.sh, start.sh);
}

TEST(Adam, BandsAboveTheActiveDegreeAreLeftAsAFullStepLeavesThem) {
  // The trainer does not step the SH bands above its active degree: with no gradient there
  // yet and zero moments, a full step leaves them exactly as they are, so skipping them must
  // give the same bits everywhere, for each degree and with either SH group alone.
  const GaussianModel start = test::random_model(1001, 3, 51);
  const std::size_t row = std::size_t(start.sh_coefficients()) * 3;
  for (int degree : {0, 1, 2}) {
    GaussianModel grads = test::random_model(1001, 3, 52);
    for (std::size_t i = 0; i < grads.sh.size(); ++i)
      if (i % row >= std::size_t(3 * sh_coefficient_count(degree))) grads.sh[i] = 0.0f;
    for (const auto& [dc, rest] : {std::pair{true, true}, std::pair{true, false}, std::pair{false, true}}) {
      GaussianModel full = start, skipped = start;
      AdamState full_state, skipped_state;
      full_state.reset_like(start);
      skipped_state.reset_like(start);
      AdamGroupMask all, active;
      all.sh_dc = active.sh_dc = dc;
      all.sh_rest = active.sh_rest = rest;
      active.sh_degree = degree;
      for (int i = 0; i < 3; ++i) {
        adam_step(full, grads, full_state, distinct_rates(), {}, all);
        adam_step(skipped, grads, skipped_state, distinct_rates(), {}, active);
      }
      EXPECT_EQ(skipped.sh, full.sh) << degree;
      EXPECT_EQ(skipped_state.first_moment.sh, full_state.first_moment.sh) << degree;
      EXPECT_EQ(skipped_state.second_moment.sh, full_state.second_moment.sh) << degree;
      EXPECT_EQ(skipped.means, full.means);
      if (dc || degree > 0) {
        EXPECT_NE(skipped.sh, start.sh);
      }
    }
  }
}

// Factors of a random SH gradient for `count` Gaussians: unit view directions, colour
// gradients with every fifth zero (Gaussians that received none).
ShGradientFactors random_factors(std::size_t count, int degree, std::mt19937& rng) {
  std::normal_distribution<float> normal(0.0f, 1.0f);
  ShGradientFactors factors;
  factors.degree = degree;
  factors.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    float d[3] = {normal(rng), normal(rng), normal(rng)};
    const float length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; ++k) {
      factors.direction[k][i] = d[k] / length;
      factors.color_grad[k][i] = i % 5 == 0 ? 0.0f : normal(rng);
    }
  }
  return factors;
}

TEST(Adam, ShGradientFactorsStepAsTheirRows) {
  // Adam forms each SH row from its factors as it steps: the parameters and moments must be
  // those the rows themselves give, for any active degree, a count that is not a multiple of
  // the lanes or of Adam's tasks, and either SH group alone.
  const GaussianModel start = test::random_model(4099, 3, 41);
  std::mt19937 rng(43);
  for (int degree : {0, 2, 3}) {
    const ShGradientFactors factors = random_factors(start.size(), degree, rng);
    GaussianModel rows = test::random_model(start.size(), 3, 44);
    const int width = start.sh_coefficients() * 3;
    for (std::size_t first = 0; first < start.size(); first += simd::kLanes)
      factors.expand(first, int(std::min<std::size_t>(simd::kLanes, start.size() - first)), width,
                     &rows.sh[first * std::size_t(width)]);
    GaussianModel garbage = rows;
    std::fill(garbage.sh.begin(), garbage.sh.end(), 1e3f);  // must not be read
    for (const auto& [dc, rest] : {std::pair{true, true}, std::pair{true, false}, std::pair{false, true}}) {
      AdamGroupMask mask;
      mask.sh_dc = dc;
      mask.sh_rest = rest;
      GaussianModel dense = start, factored = start;
      AdamState dense_state, factored_state;
      dense_state.reset_like(start);
      factored_state.reset_like(start);
      for (int i = 0; i < 3; ++i) {
        adam_step(dense, rows, dense_state, distinct_rates(), {}, mask);
        adam_step(factored, garbage, factored_state, distinct_rates(), {}, mask, &factors);
      }
      EXPECT_EQ(factored.sh, dense.sh) << degree;
      EXPECT_EQ(factored_state.first_moment.sh, dense_state.first_moment.sh) << degree;
      EXPECT_EQ(factored_state.second_moment.sh, dense_state.second_moment.sh) << degree;
      EXPECT_EQ(factored.means, dense.means);
      if (dc || degree > 0) {
        EXPECT_NE(factored.sh, start.sh);  // else every stepped row is zero
      }
    }
  }
}

TEST(Adam, RejectsMismatchedShapes) {
  GaussianModel params = test::random_model(3, 1, 1);
  AdamState state;
  state.reset_like(params);
  EXPECT_THROW(adam_step(params, test::random_model(2, 1, 2), state, {}), ArgumentError);
  EXPECT_THROW(adam_step(params, test::random_model(3, 2, 2), state, {}), ArgumentError);
  AdamState empty;
  EXPECT_THROW(adam_step(params, params, empty, {}), ArgumentError);
  ShGradientFactors factors;
  factors.resize(2);
  EXPECT_THROW(adam_step(params, params, state, {}, {}, {}, &factors), ArgumentError);
  EXPECT_EQ(state.step, 0);
}

TEST(Adam, ResetLikeZeroesMomentsAndKeepsStep) {
  GaussianModel params = test::random_model(4, 2, 1);
  AdamState state;
  state.reset_like(params);
  adam_step(params, test::random_model(4, 2, 5), state, {});
  state.reset_like(test::random_model(6, 2, 3));
  EXPECT_EQ(state.step, 1);
  ASSERT_EQ(state.first_moment.size(), 6u);
  for (float x : state.first_moment.sh) EXPECT_EQ(x, 0.0f);
  for (float x : state.second_moment.means) EXPECT_EQ(x, 0.0f);
}

TEST(Adam, BitIdenticalForAnyThreadCount) {
  const GaussianModel start = test::random_model(20000, 3, 21);
  const GaussianModel grads = test::random_model(20000, 3, 22);
  auto run = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    GaussianModel params = start;
    AdamState state;
    state.reset_like(params);
    for (int i = 0; i < 3; ++i) adam_step(params, grads, state, distinct_rates());
    return std::pair{params, state};
  };
  const auto [p1, s1] = run(1);
  const auto [p4, s4] = run(4);
  EXPECT_EQ(p1.means, p4.means);
  EXPECT_EQ(p1.log_scales, p4.log_scales);
  EXPECT_EQ(p1.quats, p4.quats);
  EXPECT_EQ(p1.opacity_logits, p4.opacity_logits);
  EXPECT_EQ(p1.sh, p4.sh);
  EXPECT_EQ(s1.first_moment.sh, s4.first_moment.sh);
  EXPECT_EQ(s1.second_moment.sh, s4.second_moment.sh);
  EXPECT_NE(p1.sh, start.sh);
}

// Every float of the five parameter groups, in kParameterGroups' order.
std::vector<float> all_values(const GaussianModel& model) {
  std::vector<float> out;
  for (const ParameterGroup& group : kParameterGroups)
    out.insert(out.end(), group.of(model).begin(), group.of(model).end());
  return out;
}

TEST(Adam, ParameterAverageLeavesTheStepsAloneAndFollowsTheIterates) {
  // The average is kept beside the steps: the parameters and moments come out bit for bit as
  // without it, and the average is the exponential moving average of the iterates, in double
  // straight from its definition, for every group (both SH rates, the SH factors' path too).
  const GaussianModel start = test::random_model(37, 3, 41);
  AdamSettings settings;
  settings.average_decay = 0.9;
  std::mt19937 rng(42);
  for (const auto& [factored, rest] : {std::pair{false, true}, std::pair{true, true}, std::pair{false, false}}) {
    SCOPED_TRACE(testing::Message() << (factored ? "SH gradient as factors" : "SH gradient as rows")
                                    << (rest ? "" : ", SH band 0 alone"));
    AdamGroupMask mask;
    mask.sh_rest = rest;
    GaussianModel plain = start, averaged = start;
    AdamState plain_state, state;
    plain_state.reset_like(plain);
    state.reset_like(averaged);
    state.start_average(averaged, 0);
    const std::vector<float> initial = all_values(start);
    std::vector<double> reference(initial.begin(), initial.end());
    for (int t = 0; t < 12; ++t) {
      const GaussianModel grads = test::random_model(37, 3, 100 + t);
      const ShGradientFactors factors = random_factors(start.size(), 3, rng);
      adam_step(plain, grads, plain_state, distinct_rates(), settings, mask, factored ? &factors : nullptr);
      adam_step(averaged, grads, state, distinct_rates(), settings, mask, factored ? &factors : nullptr);
      const std::vector<float> now = all_values(averaged);
      for (std::size_t i = 0; i < now.size(); ++i) reference[i] = 0.9 * reference[i] + 0.1 * now[i];
    }
    EXPECT_EQ(all_values(averaged), all_values(plain));
    EXPECT_EQ(all_values(state.first_moment), all_values(plain_state.first_moment));
    EXPECT_EQ(all_values(state.second_moment), all_values(plain_state.second_moment));
    const std::vector<float> average = all_values(state.averaged(averaged));
    const std::vector<float> iterate = all_values(averaged);
    double largest_gap = 0;
    for (std::size_t i = 0; i < average.size(); ++i) {
      EXPECT_NEAR(average[i], reference[i], 1e-6 + 1e-6 * std::abs(reference[i])) << "value " << i;
      largest_gap = std::max(largest_gap, std::abs(double(average[i]) - iterate[i]));
    }
    EXPECT_GT(largest_gap, 1e-3);  // the average lags the iterate: it is not the parameters
  }
}

TEST(Adam, ParameterAverageFollowsTheRowOperations) {
  GaussianModel params = test::random_model(5, 1, 51);
  AdamState state;
  state.reset_like(params);
  state.start_average(params, 7);
  EXPECT_EQ(state.average_start, 7);
  AdamSettings settings;
  settings.average_decay = 0.5;
  adam_step(params, test::random_model(5, 1, 52), state, distinct_rates(), settings);
  ASSERT_EQ(state.rows().size(), 3u);  // both moments and the offset
  const GaussianModel average = state.averaged(params);
  // Keep rows 1 and 3, then append a copy of row 0: the kept rows keep their averages, the
  // new one starts at its parameters.
  for (GaussianModel* rows : state.rows()) rows->keep_rows({0, 1, 0, 1, 0});
  params.keep_rows({0, 1, 0, 1, 0});
  params.append_rows(params.gather_rows({0}));
  for (GaussianModel* rows : state.rows()) rows->append_zero_rows(1);
  const GaussianModel after = state.averaged(params);
  EXPECT_EQ(after.mean(0)[0], average.mean(1)[0]);
  EXPECT_EQ(after.mean(1)[2], average.mean(3)[2]);
  EXPECT_EQ(after.mean(2)[1], params.mean(2)[1]);
  EXPECT_NE(after.mean(0)[0], params.mean(0)[0]);
  state.reset_like(params);  // a fresh state keeps no average
  EXPECT_FALSE(state.averaging());
  EXPECT_EQ(state.rows().size(), 2u);
}

TEST(LrSchedule, PositionScheduleDecaysLogLinearly) {
  // The official position rate: 1.6e-4 × the scene extent decaying to 1.6e-6 × it over 30000 steps.
  const float extent = 2.5f;
  const double init = 1.6e-4 * extent, final_lr = 1.6e-6 * extent;
  const ExponentialLrSchedule lr{init, final_lr, 30000};
  EXPECT_NEAR(lr(0), init, 1e-12 * init);
  EXPECT_NEAR(lr(15000), std::sqrt(init * final_lr), 1e-12 * init);  // halfway in log space
  EXPECT_NEAR(lr(30000), final_lr, 1e-12 * final_lr);
  EXPECT_NEAR(lr(40000), final_lr, 1e-12 * final_lr);  // clamped after max_steps
  EXPECT_NEAR(lr(7500), std::exp(0.75 * std::log(init) + 0.25 * std::log(final_lr)),
              1e-12 * init);
  EXPECT_EQ(lr(-1), 0.0);
  EXPECT_EQ((ExponentialLrSchedule{0.0, 0.0, 100})(5), 0.0);
  // A fraction of the schedule (what a time budget's progress reads) is the same curve.
  EXPECT_EQ(lr.at_fraction(0.25), lr(7500));
  EXPECT_NEAR(lr.at_fraction(1.0), final_lr, 1e-12 * final_lr);
  EXPECT_NEAR(lr.at_fraction(3.0), final_lr, 1e-12 * final_lr);
  EXPECT_NEAR(lr.at_fraction(-1.0), init, 1e-12 * init);
}

}  // namespace
}  // namespace splat
