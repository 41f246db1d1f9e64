#include "splat/train/official_strategy.hpp"

#include <string>

#include "splat/core/error.hpp"

namespace splat {

DensityStepReport OfficialStrategy::step_post_backward(int iteration, bool last_iteration,
                                                       TrainingState& state, GaussianModel&,
                                                       std::span<const BackwardStats> views) {
  if (views.empty()) throw ArgumentError("official strategy: a step without views");
  const int count = int(views.size());
  for (int v = 0; v + 1 < count; ++v)  // each earlier view of a batch, at its own view number
    if (control_.gathers_stats_at(iteration - count + 1 + v))
      control_.add_stats(views[std::size_t(v)].viewspace_grad_norm, views[std::size_t(v)].radii);
  // The run's last iteration gathers statistics but neither densifies nor resets: the
  // official trainer saves and scores its model at iteration N before that iteration's
  // density control, and fresh clones and splits that never get a step only depress the
  // result.
  const BackwardStats& last = views.back();
  const DensityControlReport r =
      control_.step(iteration, state.model, state.adam, last.viewspace_grad_norm, last.radii,
                    state.scene_extent, state.rng, /*stats_only=*/last_iteration, count);
  DensityStepReport report;
  report.densified = r.densified;
  report.opacity_reset = r.opacity_reset;
  report.added = r.cloned + r.split * std::size_t(control_.settings().split_count);
  report.split = r.split;
  report.pruned = r.pruned;
  report.over_budget = r.over_budget;
  report.count_after = r.count_after;
  return report;
}

std::vector<std::vector<float>*> OfficialStrategy::checkpoint_arrays() {
  DensificationStats& s = control_.stats();
  return {&s.grad_accum, &s.denom, &s.max_radii};
}

void OfficialStrategy::checkpoint_loaded(const nlohmann::json&, std::size_t gaussian_count) {
  const DensificationStats& s = control_.stats();
  if (s.grad_accum.size() != gaussian_count || s.denom.size() != gaussian_count ||
      s.max_radii.size() != gaussian_count)
    throw ArgumentError("densification statistics hold " + std::to_string(s.denom.size()) +
                        " rows, the model " + std::to_string(gaussian_count));
}

}  // namespace splat
