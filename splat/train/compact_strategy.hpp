#pragma once
// The compact density strategy: the model grows only where the image still asks for more
// Gaussians, and loses those that make nothing visible, so each scene ends with the count
// it needs rather than the official recipe's habit of several hundred thousand.
//
//   - Growth: the official criterion (mean view-space gradient over the views since the
//     last step) picks the candidates, largest gradient first, and at most a fixed fraction
//     of the model is added per step; the official clone (small) and split (large) place
//     them. When the image is fitted, the gradients fall below the threshold and growth
//     stops by itself.
//   - Pruning: transparent Gaussians at every growth step, and at the end of every window
//     (one epoch of the training views by default) those whose blending weight over the
//     window stayed below a few pixels' worth: hidden inside or behind the surface, or too
//     faint to matter. No opacity resets: pruning by contribution does their job without
//     setting the whole model back.
//   - A resolution warm-up: the first iterations train on reduced images, where a step is a
//     fraction of the cost and the coarse structure forms just as well.
// Settings: compact_settings.hpp.
#include "splat/optim/density_control.hpp"
#include "splat/train/compact_settings.hpp"
#include "splat/train/density_strategy.hpp"
#include "splat/train/points_near_bounds.hpp"

namespace splat {

class CompactStrategy final : public DensityStrategy {
 public:
  // `density` supplies the shared clone/split settings (percent_dense, split count and
  // divisor) and the hard cap max_gaussians; `train_views` sets the default window.
  // `near_bounds`: the training cameras' near bounds (points_near_bounds.hpp) that
  // prune_before_points compares with; none, and that pruning does nothing.
  CompactStrategy(const CompactSettings& settings, const DensityControlSettings& density,
                  std::size_t train_views, unsigned seed, std::size_t gaussian_count,
                  std::vector<CameraNearBound> near_bounds = {});

  std::string name() const override { return "compact"; }
  DensityStepReport step_post_backward(int iteration, bool last_iteration, TrainingState& state,
                                       GaussianModel& grads, std::span<const BackwardStats> views) override;
  void step_post_optimizer(int iteration, TrainingState& state, float means_lr) override;
  std::vector<std::vector<float>*> checkpoint_arrays() override;
  nlohmann::json checkpoint_state() const override;
  void checkpoint_loaded(const nlohmann::json& state, std::size_t gaussian_count) override;
  nlohmann::json metrics() const override;

  int prune_window() const { return window_; }

 private:
  void add_regularization(const GaussianModel& model, GaussianModel& grads) const;
  void grow(int iteration, TrainingState& state, DensityStepReport& report);
  void prune_by_weight(float threshold, TrainingState& state, DensityStepReport& report);
  void prune_before_points(TrainingState& state, DensityStepReport& report);
  // Whether the decay, not the resets, acts at this point of the schedule.
  bool decays_opacity(int phase) const;
  static void decay_opacity(GaussianModel& model, float fraction);
  void add_position_noise(int iteration, TrainingState& state, float means_lr);
  // Removes the rows `keep` marks 0 from the model and every array aligned with it, and
  // counts them as pruned; returns how many.
  std::size_t remove_rows(const std::vector<std::uint8_t>& keep, TrainingState& state,
                          DensityStepReport& report);
  bool counts_views() const { return settings_.prune_min_view_share > 0; }
  std::vector<std::vector<float>*> statistics();
  AlignedRows rows(TrainingState& state);
  void reset_stats(std::size_t n);

  CompactSettings settings_;
  DensityControlSettings density_;
  unsigned seed_;
  int window_;  // iterations per pruning window
  std::vector<CameraNearBound> near_bounds_;

  // [N] statistics, aligned with the model's rows.
  std::vector<float> grad_accum_;     // Σ view-space gradient norm since the last growth step
  std::vector<float> visible_views_;  // views where the Gaussian was drawn, same period
  std::vector<float> window_weight_;  // Σ blending weight (full-size pixels) in this window
  // With prune_min_view_share: views of this window that drew the Gaussian (an extra
  // checkpoint array only then, so that older checkpoints load as they are).
  std::vector<float> window_views_;
  int window_view_count_ = 0;  // views in this window so far

  // Decisions, for metrics.json.
  int last_growth_iteration_ = 0;  // last growth step that added Gaussians
  std::size_t total_added_ = 0, total_pruned_ = 0;
  std::size_t total_pruned_before_points_ = 0;  // of total_pruned_
};

}  // namespace splat
