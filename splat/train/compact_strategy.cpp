#include "splat/train/compact_strategy.hpp"

#include <algorithm>
#include <cmath>
#include <tbb/parallel_for.h>

#include "splat/core/error.hpp"
#include "splat/core/random.hpp"
#include "splat/optim/step_events.hpp"
#include "splat/optim/relocation.hpp"
#include "splat/raster/projection_math.hpp"

namespace splat {

namespace {

// A counter-based random stream (splitmix64): the value for (seed, iteration, index) is a pure
// function of them, so per-Gaussian noise can be drawn in parallel and does not depend on
// thread count.
// Three standard normals for one Gaussian (Box–Muller on four 24-bit uniforms).
Vec3<float> normal3(unsigned seed, int iteration, std::size_t index) {
  const std::uint64_t key = splitmix64(splitmix64(seed) ^ (std::uint64_t(iteration) << 40) ^ index);
  const std::uint64_t a = splitmix64(key), b = splitmix64(key ^ 0x5851f42d4c957f2dull);
  auto uniform = [](std::uint64_t bits) { return double((bits >> 40) & 0xffffff) / 16777216.0; };
  const double r0 = std::sqrt(-2.0 * std::log(1.0 - uniform(a))), t0 = 2.0 * M_PI * uniform(a >> 24 << 40);
  const double r1 = std::sqrt(-2.0 * std::log(1.0 - uniform(b))), t1 = 2.0 * M_PI * uniform(b >> 24 << 40);
  return {float(r0 * std::cos(t0)), float(r0 * std::sin(t0)), float(r1 * std::cos(t1))};
}

// logit(keep · sigmoid(x)) = log(keep) − log((1 − keep) + e^−x), written so that neither
// exponential can overflow: a Gaussian pruned long ago to a logit of −100 stays finite.
float scaled_opacity_logit(float x, float keep) {
  if (x >= 0) return std::log(keep) - std::log((1.0f - keep) + std::exp(-x));
  return std::log(keep) + x - std::log1p((1.0f - keep) * std::exp(x));
}

// Where training stands in its growth schedule: a time-budgeted run maps its wall clock onto
// the iteration schedule (state.schedule_iteration); otherwise the iteration itself.
int schedule_phase(const TrainingState& state, int iteration) {
  return state.schedule_iteration > 0 ? state.schedule_iteration : iteration;
}

}  // namespace

CompactStrategy::CompactStrategy(const CompactSettings& settings,
                                 const DensityControlSettings& density, std::size_t train_views,
                                 unsigned seed, std::size_t gaussian_count,
                                 std::vector<CameraNearBound> near_bounds)
    : settings_(settings),
      density_(density),
      seed_(seed),
      near_bounds_(std::move(near_bounds)) {
  if (settings.grow_interval < 1) throw ArgumentError("compact strategy: grow_interval must be >= 1");
  if (!(settings.grow_max_fraction >= 0)) throw ArgumentError("compact strategy: grow_max_fraction must be >= 0");
  // Views come in shuffled epochs, so only a window of two epochs' length is sure to hold
  // every training view: a Gaussian seen from a few views only is not pruned for being unseen.
  window_ = settings.prune_window > 0 ? settings.prune_window
                                      : std::max<int>(settings.grow_interval, 2 * int(train_views));
  reset_stats(gaussian_count);
  window_weight_.assign(gaussian_count, 0.0f);
  if (counts_views()) window_views_.assign(gaussian_count, 0.0f);
}

std::vector<std::vector<float>*> CompactStrategy::statistics() {
  std::vector<std::vector<float>*> arrays = {&grad_accum_, &visible_views_, &window_weight_};
  if (counts_views()) arrays.push_back(&window_views_);
  return arrays;
}

void CompactStrategy::reset_stats(std::size_t n) {
  grad_accum_.assign(n, 0.0f);
  visible_views_.assign(n, 0.0f);
}

AlignedRows CompactStrategy::rows(TrainingState& state) {
  return {state.model, state.adam, statistics()};
}

void CompactStrategy::add_regularization(const GaussianModel& model, GaussianModel& grads) const {
  const std::size_t n = model.size();
  if (n == 0) return;
  // ∂/∂logit of λ·mean(sigmoid(logit)) and ∂/∂log_scale of λ·mean(exp(log_scale)).
  const float opacity_coefficient = settings_.opacity_regularization / float(n);
  const float scale_coefficient = settings_.scale_regularization / float(3 * n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      if (opacity_coefficient > 0) {
        const float o = model.opacity(i);
        grads.opacity_logits[i] += opacity_coefficient * o * (1.0f - o);
      }
      if (scale_coefficient > 0) {
        const Vec3<float> scale = model.scale(i);
        for (int a = 0; a < 3; ++a) grads.log_scales[3 * i + a] += scale_coefficient * scale[a];
      }
    }
  });
}

DensityStepReport CompactStrategy::step_post_backward(int iteration, bool last_iteration,
                                                      TrainingState& state, GaussianModel& grads,
                                                      std::span<const BackwardStats> views) {
  const std::size_t n = state.model.size();
  if (views.empty()) throw ArgumentError("compact strategy: a step without views");
  for (const BackwardStats& stats : views)
    if (grad_accum_.size() != n || stats.viewspace_grad_norm.size() != n || stats.radii.size() != n ||
        stats.blend_weight.size() != n)
      throw ArgumentError("compact strategy: statistics for " + std::to_string(grad_accum_.size()) +
                          " Gaussians, the model has " + std::to_string(n));
  if (settings_.opacity_regularization > 0 || settings_.scale_regularization > 0)
    add_regularization(state.model, grads);

  // Blending weights at a reduced size count reduced pixels: scale them to full-size ones.
  const float pixel_scale = float(state.resolution_divisor * state.resolution_divisor);
  for (const BackwardStats& stats : views)
    for (std::size_t i = 0; i < n; ++i) {
      if (stats.radii[i] <= 0) continue;
      grad_accum_[i] += stats.viewspace_grad_norm[i];
      visible_views_[i] += 1.0f;
      const float weight = stats.blend_weight[i] * pixel_scale;
      window_weight_[i] = settings_.prune_by_peak_weight ? std::max(window_weight_[i], weight)
                                                         : window_weight_[i] + weight;
      if (counts_views() && weight >= settings_.prune_weight) window_views_[i] += 1.0f;
    }
  window_view_count_ += int(views.size());

  DensityStepReport report;
  report.count_after = n;
  if (last_iteration) return report;
  const CompactSettings& s = settings_;
  const int count = int(views.size());
  const int phase = schedule_phase(state, iteration);
  if (iteration > s.grow_from && phase <= s.grow_until && step_reaches_multiple(iteration, count, s.grow_interval))
    grow(iteration, state, report);
  const float prune_threshold = phase > s.grow_until && s.prune_weight_after_growth > 0
                                    ? s.prune_weight_after_growth
                                    : s.prune_weight;
  const bool window_ends = step_reaches_multiple(iteration, count, window_);
  if (prune_threshold > 0 && iteration >= s.grow_from && phase <= s.prune_until && window_ends)
    prune_by_weight(prune_threshold, state, report);
  // Geometry, not contribution: kept up to the end, since what sits in front of the points
  // is wrong however late it got there.
  if (s.prune_before_points > 0 && !near_bounds_.empty() && iteration >= s.grow_from && window_ends)
    prune_before_points(state, report);
  if (window_ends) {
    std::fill(window_weight_.begin(), window_weight_.end(), 0.0f);
    std::fill(window_views_.begin(), window_views_.end(), 0.0f);
    window_view_count_ = 0;
  }
  if (s.opacity_reset_interval > 0 && phase <= s.grow_until && !decays_opacity(phase) &&
      step_reaches_multiple(iteration, count, s.opacity_reset_interval)) {
    reset_opacity(state.model, state.adam, s.opacity_reset_value);
    report.opacity_reset = true;
  }
  report.count_after = state.model.size();
  return report;
}

void CompactStrategy::grow(int iteration, TrainingState& state, DensityStepReport& report) {
  GaussianModel& model = state.model;
  const std::size_t n = model.size();
  std::vector<float> mean_grad(n, 0.0f);
  for (std::size_t i = 0; i < n; ++i)
    if (visible_views_[i] > 0) mean_grad[i] = grad_accum_[i] / visible_views_[i];

  DensityControlSettings growth = density_;
  growth.densify_grad_threshold = settings_.grow_grad_threshold;
  const std::size_t step_room = n + std::size_t(std::floor(settings_.grow_max_fraction * double(n)));
  growth.max_gaussians =
      density_.max_gaussians > 0 ? std::min(step_room, density_.max_gaussians) : step_room;
  const DensifyCandidates candidates =
      select_densify_candidates(model, mean_grad, growth, state.scene_extent);

  AlignedRows aligned = rows(state);
  std::size_t added = 0;
  std::vector<std::uint8_t> keep(n, 1);
  if (settings_.grow_by_sampling) {
    // The candidates say how many; live Gaussians drawn by opacity say where.
    std::vector<std::uint8_t> alive(n);
    for (std::size_t i = 0; i < n; ++i)
      alive[i] = model.opacity(i) >= settings_.prune_opacity;
    const std::vector<std::size_t> sources = sample_by_opacity(
        model, alive, candidates.clone.size() + candidates.split.size(), state.rng);
    added = add_relocated_copies(aligned, sources, settings_.prune_opacity);
  } else {
    aligned.append_copies(candidates.clone, model.gather_rows(candidates.clone));
    std::vector<std::size_t> offspring_sources;
    const GaussianModel born =
        split_offspring(model, candidates.split, growth, state.rng, offspring_sources);
    aligned.append_copies(offspring_sources, born);
    added = candidates.clone.size() + offspring_sources.size();
    for (std::size_t i : candidates.split) keep[i] = 0;
    report.split += candidates.split.size();
  }

  // Transparent Gaussians: moved onto live ones, or pruned.
  const std::size_t total = model.size();
  keep.resize(total, 1);
  std::vector<std::size_t> dead;
  for (std::size_t i = 0; i < total; ++i)
    if (keep[i] && model.opacity(i) < settings_.prune_opacity) dead.push_back(i);
  std::size_t pruned = 0;
  if (settings_.relocate_dead && !dead.empty()) {
    std::vector<std::uint8_t> alive(keep);
    for (std::size_t i : dead) alive[i] = 0;
    const std::vector<std::size_t> sources = sample_by_opacity(model, alive, dead.size(), state.rng);
    if (sources.size() == dead.size())
      report.relocated += relocate_rows(aligned, dead, sources, settings_.prune_opacity);
  } else {
    for (std::size_t i : dead) keep[i] = 0;
    pruned = dead.size();
  }
  aligned.keep(keep);
  reset_stats(model.size());

  report.densified = true;
  report.added += added;
  report.pruned += pruned;
  report.over_budget += candidates.over_budget;
  total_added_ += added;
  total_pruned_ += pruned;
  if (added > 0) last_growth_iteration_ = iteration;
}

void CompactStrategy::prune_by_weight(float threshold, TrainingState& state,
                                       DensityStepReport& report) {
  const std::size_t n = state.model.size();
  std::vector<std::uint8_t> keep(n, 1);
  const float min_views = settings_.prune_min_view_share * float(window_view_count_);
  for (std::size_t i = 0; i < n; ++i)
    keep[i] = !(window_weight_[i] < threshold || (counts_views() && window_views_[i] < min_views));
  remove_rows(keep, state, report);
}

void CompactStrategy::prune_before_points(TrainingState& state, DensityStepReport& report) {
  const GaussianModel& model = state.model;
  const std::size_t n = model.size();
  std::vector<std::uint8_t> keep(n, 1);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const glm::vec3 p(model.means[3 * i], model.means[3 * i + 1], model.means[3 * i + 2]);
      keep[i] = !in_front_of_points(near_bounds_, p, settings_.prune_before_points);
    }
  });
  total_pruned_before_points_ += remove_rows(keep, state, report);
}

std::size_t CompactStrategy::remove_rows(const std::vector<std::uint8_t>& keep, TrainingState& state,
                                         DensityStepReport& report) {
  const std::size_t pruned = std::size_t(std::count(keep.begin(), keep.end(), std::uint8_t(0)));
  if (pruned == 0) return 0;
  AlignedRows aligned = rows(state);
  aligned.keep(keep);
  report.densified = true;
  report.pruned += pruned;
  total_pruned_ += pruned;
  return pruned;
}

void CompactStrategy::step_post_optimizer(int iteration, TrainingState& state, float means_lr) {
  const int phase = schedule_phase(state, iteration);
  if (iteration >= settings_.grow_from && phase <= settings_.grow_until && decays_opacity(phase))
    decay_opacity(state.model, settings_.opacity_decay);
  if (settings_.noise_lr > 0) add_position_noise(iteration, state, means_lr);
}

bool CompactStrategy::decays_opacity(int phase) const {
  return settings_.opacity_decay > 0 && phase >= settings_.opacity_decay_from;
}

void CompactStrategy::decay_opacity(GaussianModel& model, float fraction) {
  // In the opacity itself, not its logit: a fixed share of every Gaussian's coverage, which an
  // opaque one the views agree on wins back in a step and a faint unconstrained one does not.
  const float keep = 1.0f - fraction;
  std::vector<float>& logits = model.opacity_logits;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, logits.size(), 4096), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i)
      logits[i] = scaled_opacity_logit(logits[i], keep);
  });
}

void CompactStrategy::add_position_noise(int iteration, TrainingState& state, float means_lr) {
  // MCMC's exploration noise: N(0, Σ) scaled by the means' step, switched on smoothly as the
  // opacity falls below ~0.005 (sigmoid(100·((1 − o) − 0.995))), so opaque Gaussians stay put.
  GaussianModel& model = state.model;
  const float scale = settings_.noise_lr * means_lr;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, model.size(), 4096), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const float o = model.opacity(i);
      const float gate = sigmoid(100.0f * ((1.0f - o) - 0.995f));
      if (gate < 1e-7f) continue;
      const Mat3<float> cov = covariance_3d(model.scale(i), model.rotation(i));
      const Vec3<float> offset = cov * normal3(seed_, iteration, i) * (gate * scale);
      for (int a = 0; a < 3; ++a) model.means[3 * i + a] += offset[a];
    }
  });
}

std::vector<std::vector<float>*> CompactStrategy::checkpoint_arrays() {
  return statistics();
}

nlohmann::json CompactStrategy::checkpoint_state() const {
  return {{"last_growth_iteration", last_growth_iteration_},
          {"total_added", total_added_},
          {"total_pruned", total_pruned_},
          {"window_view_count", window_view_count_},
          {"total_pruned_before_points", total_pruned_before_points_}};
}

void CompactStrategy::checkpoint_loaded(const nlohmann::json& state, std::size_t gaussian_count) {
  if (grad_accum_.size() != gaussian_count || visible_views_.size() != gaussian_count ||
      window_weight_.size() != gaussian_count || (counts_views() && window_views_.size() != gaussian_count))
    throw ArgumentError("compact strategy statistics hold " + std::to_string(grad_accum_.size()) +
                        " rows, the model " + std::to_string(gaussian_count));
  last_growth_iteration_ = state.value("last_growth_iteration", 0);
  total_added_ = state.value("total_added", std::size_t(0));
  total_pruned_ = state.value("total_pruned", std::size_t(0));
  window_view_count_ = state.value("window_view_count", 0);
  total_pruned_before_points_ = state.value("total_pruned_before_points", std::size_t(0));
}

nlohmann::json CompactStrategy::metrics() const {
  return {{"last_growth_iteration", last_growth_iteration_},
          {"gaussians_added", total_added_},
          {"gaussians_pruned", total_pruned_},
          {"gaussians_pruned_before_points", total_pruned_before_points_},
          {"near_bounds", near_bounds_.size()},
          {"prune_window", window_}};
}

}  // namespace splat
