#include "splat/train/official_strategy.hpp"

#include <string>

#include "splat/core/error.hpp"

namespace splat {

DensityStepReport OfficialStrategy::step_post_backward(int iteration, bool last_iteration,
                                                       TrainingState& state, GaussianModel&,
                                                       const BackwardStats& stats) {
  // The run's last iteration gathers statistics but neither densifies nor resets: the
  // official trainer saves and scores its model at iteration N before that iteration's
  // density control, and fresh clones and splits that never get a step only depress the
  // result.
  const DensityControlReport r =
      control_.step(iteration, state.model, state.adam, stats.viewspace_grad_norm, stats.radii,
                    state.scene_extent, state.rng, /*stats_only=*/last_iteration);
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
