#pragma once
// Density control as a strategy the training loop calls at fixed points of every iteration
// (the shape of gsplat's Strategy: hooks before and after the backward pass), so that the
// official recipe and the compact one share one loop:
//
//   render, loss, backward (at the size the trainer's resolution schedule gives)
//   step_post_backward(it, ...)     statistics, then growth / pruning / resets of rows
//   Adam step on the groups the report leaves active
//   step_post_optimizer(it, ...)    anything that acts on the updated parameters
//
// A strategy owns whatever it accumulates between decisions (statistics rows aligned with
// the model) and applies every row operation to the model, both Adam moments and those
// statistics alike, so nothing ever falls out of step with the rows.
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "splat/gaussians/gaussian_model.hpp"
#include "splat/optim/adam.hpp"

namespace splat {

struct SplatTrainingConfig;
struct Dataset;
struct CompactSettings;

// What the loop lends a strategy for one hook call.
struct TrainingState {
  GaussianModel& model;
  AdamState& adam;
  std::mt19937& rng;  // the trainer's one random stream (view order, splits, ...)
  float scene_extent;
  // Where the run stands in the schedule's terms: the iteration, or scaled to the run's
  // budget (SplatTrainingConfig::schedule_follows_budget). Phases (grow until, prune until)
  // compare with it; intervals count real iterations. 0 = the iteration itself.
  int schedule_iteration = 0;
  // The step trained on images reduced by this factor (resolution_schedule.hpp).
  int resolution_divisor = 1;
};

// Per-Gaussian results of the iteration's backward pass, all [N] for the current model.
struct BackwardStats {
  std::span<const float> viewspace_grad_norm;  // ‖∂L/∂(2D mean)‖ in NDC units
  std::span<const std::int32_t> radii;         // screen radius in px, 0 when not drawn
  std::span<const float> blend_weight;         // Σ over pixels of Tᵢαᵢ (pixels it covers)
  int image_width = 0, image_height = 0;       // of the image this iteration trained on
};

// What a hook did, for the loop (which optimiser groups to skip) and the logs.
struct DensityStepReport {
  bool densified = false;      // rows were added or removed: skip this iteration's Adam step
  bool opacity_reset = false;  // opacities were replaced: skip the opacity group's step
  std::size_t added = 0;       // Gaussians born (clones, split offspring, growth)
  std::size_t split = 0;       // of which split originals replaced (official)
  std::size_t pruned = 0;      // Gaussians removed
  std::size_t relocated = 0;   // dead Gaussians moved onto live ones
  std::size_t over_budget = 0; // candidates left out because of the Gaussian cap
  std::size_t count_after = 0;
};

class DensityStrategy {
 public:
  virtual ~DensityStrategy() = default;
  virtual std::string name() const = 0;

  // Between the backward pass and the optimiser step. `grads` holds the step's gradients (a
  // strategy may add its regularisers' gradients to it; it is not valid for the optimiser
  // once the report says `densified`). `views` holds the statistics of each view the step
  // trained on, in batch order (one unless --batch), and `iteration` counts views: it is
  // the last one's (optim/step_events.hpp says which events fall in the step).
  // `last_iteration` is the run's final step: statistics only, the model is not changed then.
  virtual DensityStepReport step_post_backward(int iteration, bool last_iteration,
                                               TrainingState& state, GaussianModel& grads,
                                               std::span<const BackwardStats> views) = 0;

  // After the optimiser step (also when the report skipped it), with the learning rate of
  // the means that step used.
  virtual void step_post_optimizer(int /*iteration*/, TrainingState& /*state*/,
                                   float /*means_lr*/) {}

  // The rows of statistics a checkpoint must hold to resume exactly, each [N], in a fixed
  // order. Loading writes into the same vectors, then calls checkpoint_loaded.
  virtual std::vector<std::vector<float>*> checkpoint_arrays() = 0;
  // Scalar state (counters, decisions taken) for the checkpoint header.
  virtual nlohmann::json checkpoint_state() const { return nlohmann::json::object(); }
  // After a checkpoint's arrays were read into checkpoint_arrays(): `state` is what
  // checkpoint_state() wrote. Throws ArgumentError if it does not fit `gaussian_count` rows.
  virtual void checkpoint_loaded(const nlohmann::json& state, std::size_t gaussian_count) = 0;

  // Strategy-specific figures for metrics.json (e.g. when growth stopped and why).
  virtual nlohmann::json metrics() const { return nlohmann::json::object(); }
};

// The compact settings that act on `dataset`: the configured ones, with the opacity decay and
// the view-share prune off on data without a point cloud while `real_capture_only` (synthetic
// scenes keep the resets and the few-view Gaussians they were tuned with).
CompactSettings compact_settings_for(const CompactSettings& configured, const Dataset& dataset);

// The strategy named by config.strategy, for training on `dataset` (its training views and,
// where a setting asks, its cameras and points) and a model of `gaussian_count` rows.
std::unique_ptr<DensityStrategy> make_density_strategy(const SplatTrainingConfig& config,
                                                       const Dataset& dataset,
                                                       std::size_t gaussian_count);

}  // namespace splat
