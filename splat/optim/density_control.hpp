#pragma once
// Adaptive density control as the official 3DGS trainer does it (train.py and
// GaussianModel.densify_and_prune / reset_opacity, 2024 version): clone small Gaussians and
// split large ones where the view-space positional gradient is large, prune transparent ones,
// and periodically reset opacities.
//
// Row operations apply to the model, both Adam moments and the statistics alike: survivors
// keep their moments, new rows start with zero moments (the official concatenates zeros),
// and the shared Adam step count is kept.
//
// Note for the caller (the training loop). Within one iteration the official order is:
// backward → DensityControl::step (stats, densify, opacity reset) → optimiser step. After
// densification every parameter tensor is new and has no gradient, so PyTorch's Adam skips
// the whole step (no update, no moment change, no step count): when the report says
// `densified`, do not call adam_step. When it says only `opacity_reset`, the opacity tensor
// alone is new: step with AdamGroupMask{.opacity = false}.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <random>
#include <span>
#include <vector>

#include "splat/gaussians/gaussian_model.hpp"
#include "splat/optim/adam.hpp"

namespace splat {

struct DensityControlSettings {
  // Schedule, with iterations counted from 1 as in train.py.
  int densify_from_iter = 500;        // densify only after this iteration
  int densify_until_iter = 15000;     // stats, densification and resets only before this
  int densification_interval = 100;   // densify at multiples of this
  int opacity_reset_interval = 3000;  // reset opacities at multiples of this
  // The official trainer also resets at densify_from_iter on a white background.
  bool white_background = false;

  // Densification. The two factors of the scene extent are double because the official
  // trainer multiplies in Python (double) and compares in float.
  float densify_grad_threshold = 2e-4f;  // mean ‖∂L/∂(NDC 2D mean)‖ that triggers it
  double percent_dense = 0.01;           // clone if max scale ≤ this × extent, else split
  int split_count = 2;                   // Gaussians replacing one split Gaussian
  float split_scale_divisor = 1.6f;      // their scale: original / (0.8 × split_count)

  // Pruning.
  float min_opacity = 0.005f;
  float max_screen_size = 20.0f;       // px; only after the first opacity reset
  double max_world_size_factor = 0.1;  // × extent; only after the first opacity reset
  // The official densification_postfix zeroes max_radii2D, and it runs (clone, then split)
  // before the prune test, so `max_radii2D > 20` never prunes anything there. False
  // reproduces that; true prunes by screen radius as the paper describes, with the radii
  // accumulated since the last densification.
  bool prune_by_screen_size = false;

  float opacity_reset_value = 0.01f;  // reset caps opacity at this

  // Gaussian budget, 0 = unlimited. Densification never takes the count above it: when the
  // clone and split candidates would (each adds one Gaussian net), only the candidates with
  // the largest mean gradient (accum / denom, the value compared with the threshold; ties to
  // the lower index) are densified, as many as fit. Pruning is unaffected, and a model that
  // starts above the budget is not cut down, only not grown.
  std::size_t max_gaussians = 0;
};

// Per-Gaussian statistics between densifications (official xyz_gradient_accum, denom,
// max_radii2D).
struct DensificationStats {
  std::vector<float> grad_accum;   // [N] Σ ‖view-space positional gradient‖ over visible views
  std::vector<float> denom;        // [N] number of views where the Gaussian was visible
  std::vector<float> max_radii;    // [N] largest screen radius seen (px)

  std::size_t size() const { return denom.size(); }
  // n rows of zeros.
  void reset(std::size_t n);
  // Keeps the rows whose flag is non-zero, in order.
  void keep_rows(const std::vector<std::uint8_t>& keep);
};

struct DensityControlReport {
  bool densified = false;      // densify_and_prune ran: skip this iteration's Adam step
  bool opacity_reset = false;  // opacities were reset
  std::size_t cloned = 0;
  std::size_t split = 0;           // Gaussians split (each replaced by split_count)
  std::size_t pruned = 0;
  std::size_t over_budget = 0;     // candidates left out because of max_gaussians
  std::size_t count_after = 0;     // Gaussians after this step
};

class DensityControl {
 public:
  DensityControl(const DensityControlSettings& settings, std::size_t gaussian_count);

  const DensityControlSettings& settings() const { return settings_; }
  const DensificationStats& stats() const { return stats_; }
  DensificationStats& stats() { return stats_; }

  // Everything train.py does between backward and the optimiser step, for `iteration`
  // (from 1): stats, then densify_and_prune on the schedule, then the opacity reset.
  // view_grad_norms[i] is ‖∂L/∂(mean2D_i)‖ with the 2D mean in NDC-scaled units as the
  // official rasterizer reports it; radii[i] the screen radius (0 when not visible).
  // `rng` drives the split samples and is used only when something splits. With
  // `stats_only` (the run's last iteration) the statistics are gathered but nothing is
  // densified, pruned or reset. A step over a batch of `views` views (step_events.hpp) adds
  // the other views' statistics first (add_stats) and passes its last view's here as
  // `iteration`: the events due at any of its views happen once, after all of them.
  DensityControlReport step(int iteration, GaussianModel& model, AdamState& adam,
                            std::span<const float> view_grad_norms,
                            std::span<const std::int32_t> radii, float scene_extent,
                            std::mt19937& rng, bool stats_only = false, int views = 1);

  // True when a step over the `views` views up to `iteration` resets the opacities.
  bool resets_opacity_at(int iteration, int views = 1) const;
  // Whether view `iteration` still gathers statistics.
  bool gathers_stats_at(int iteration) const { return iteration < settings_.densify_until_iter; }

  // add_densification_stats: for every Gaussian with radius > 0, accumulate the gradient
  // norm, count the view and track the largest radius.
  void add_stats(std::span<const float> view_grad_norms, std::span<const std::int32_t> radii);

  // densify_and_prune: clone, split, prune, then zero the stats. `max_screen_size` is the
  // official size_threshold (none before the first opacity reset).
  DensityControlReport densify_and_prune(GaussianModel& model, AdamState& adam,
                                         float scene_extent,
                                         std::optional<float> max_screen_size,
                                         std::mt19937& rng);

 private:
  DensityControlSettings settings_;
  DensificationStats stats_;
};

// ---- Pieces the strategies share ------------------------------------------------------

// The same row operations on a model, its Adam state's rows (AdamState::rows: both moments and
// any parameter average's offset) and any per-row statistics, so they stay aligned: new rows
// get zero moments (the official concatenates zeros), a zero offset (their average starts at
// their parameters) and a copy of their source's statistics; the shared Adam step count is kept.
struct AlignedRows {
  GaussianModel& model;
  AdamState& adam;
  std::vector<std::vector<float>*> stats;  // each [N]

  // Appends `born` (one row per entry of `sources`, the rows they were made from).
  void append_copies(const std::vector<std::size_t>& sources, const GaussianModel& born);
  // Keeps the rows whose flag is non-zero, in order.
  void keep(const std::vector<std::uint8_t>& flags);
};

struct DensifyCandidates {
  std::vector<std::size_t> clone;  // ascending
  std::vector<std::size_t> split;  // ascending
  std::size_t over_budget = 0;     // left out because of settings.max_gaussians
};

// Gaussians whose mean gradient `grads[i]` reaches settings.densify_grad_threshold, small ones
// (max scale ≤ percent_dense × extent) to clone and large ones to split, trimmed to
// settings.max_gaussians by largest gradient first (ties to the lower index).
DensifyCandidates select_densify_candidates(const GaussianModel& model,
                                            const std::vector<float>& grads,
                                            const DensityControlSettings& settings,
                                            float scene_extent);

// split_count new Gaussians per source, in the official order (all sources for the first
// sample, then all for the second, ...): mean + R(q)·(scale ⊙ z) with z ~ N(0, I),
// log_scale = log(scale / divisor), everything else copied. `offspring_sources` receives the
// source row of each new Gaussian.
GaussianModel split_offspring(const GaussianModel& model, const std::vector<std::size_t>& sources,
                              const DensityControlSettings& settings, std::mt19937& rng,
                              std::vector<std::size_t>& offspring_sources);

// Caps every opacity at `cap`: stored ← logit(min(sigmoid(stored), cap)), and zeroes
// the opacity moments (the official replace_tensor_to_optimizer; and the parameter average's
// offset, if one is kept, so the average restarts at the capped values); step count kept.
void reset_opacity(GaussianModel& model, AdamState& adam, float cap);

}  // namespace splat
