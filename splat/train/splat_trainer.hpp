#pragma once
// The Gaussian-splatting trainer: the official 3DGS optimisation loop on the CPU rasterizer.
// One step() is one iteration: pick a training view, render, (1 − λ)·L1 + λ·(1 − SSIM),
// backward, density control (the configured DensityStrategy's hooks), Adam. No printing: the
// command line reports progress.
#include <cmath>
#include <filesystem>
#include <memory>
#include <utility>
#include <random>
#include <string>
#include <vector>

#include "splat/core/error.hpp"
#include "splat/data/dataset.hpp"
#include "splat/optim/adam.hpp"
#include "splat/optim/far_steps.hpp"
#include "splat/optim/photometric_loss.hpp"
#include "splat/raster/rasterizer.hpp"
#include "splat/train/batch_exchange.hpp"
#include "splat/train/density_strategy.hpp"
#include "splat/train/evaluation.hpp"
#include "splat/train/exposure_compensation.hpp"
#include "splat/train/initial_model.hpp"
#include "splat/train/pose_alignment.hpp"
#include "splat/train/process_group.hpp"
#include "splat/train/training_config.hpp"
#include "splat/train/view_batch.hpp"

namespace splat {

// Training produced NaN or Inf: which iteration and which parameter group (or "loss").
class TrainingDiverged : public Error {
 public:
  TrainingDiverged(int iteration, const std::string& group)
      : Error("training diverged at iteration " + std::to_string(iteration) + ": non-finite " +
              group),
        iteration_(iteration), group_(group) {}
  int iteration() const { return iteration_; }
  const std::string& group() const { return group_; }

 private:
  int iteration_;
  std::string group_;
};

struct IterationTimings {  // milliseconds
  double forward = 0, loss = 0, backward = 0, optimizer = 0, densify = 0;
  // The rasterizer's stages inside forward and backward (splats only; 0 for the NeRF).
  double project = 0, bin_sort = 0, blend = 0, blend_backward = 0, project_backward = 0;
  // Over several ranks: exchanging and summing the batch's gradients and statistics (0 alone).
  double exchange = 0;

  // Every figure by name: the five stages, then the rasterizer's parts.
  static constexpr std::pair<const char*, double IterationTimings::*> kFields[] = {
      {"forward", &IterationTimings::forward},         {"loss", &IterationTimings::loss},
      {"backward", &IterationTimings::backward},       {"optimizer", &IterationTimings::optimizer},
      {"densify", &IterationTimings::densify},         {"project", &IterationTimings::project},
      {"bin_sort", &IterationTimings::bin_sort},       {"blend", &IterationTimings::blend},
      {"blend_backward", &IterationTimings::blend_backward},
      {"project_backward", &IterationTimings::project_backward}, {"exchange", &IterationTimings::exchange}};

  double total() const { return forward + loss + backward + exchange + optimizer + densify; }
  IterationTimings& operator+=(const IterationTimings& o) {
    for (const auto& [name, field] : kFields) this->*field += o.*field;
    return *this;
  }
};

struct StepResult {
  double loss = 0, l1 = 0, ssim = 0;
  int resolution_divisor = 1;  // the image trained on was 1/this of the full size
  IterationTimings timings;
  DensityStepReport density;
  ExchangeReport exchange;  // several ranks only
};

class SplatTrainer {
 public:
  // Initialises the model from the dataset's points, or at random where the config and the
  // cameras say (initial_model.hpp).
  SplatTrainer(const Dataset& dataset, const SplatTrainingConfig& config);

  // One step: config().batch views (one iteration each: iteration() advances by the batch).
  // Throws TrainingDiverged on a non-finite loss or parameter.
  StepResult step();

  // Renders `views` with the current model (active SH bands) and scores them. If `renders`
  // is given it receives the clamped images.
  Evaluation evaluate(const std::vector<DatasetView>& views, std::vector<Image>* renders = nullptr);
  // The image evaluate() scores for one camera (clamped to [0, 1]), without scoring it: what
  // splat-eval times as the render cost.
  Image render(const Camera& camera) const;
  // The camera evaluate() renders `view` with: its recorded one, or under pose refinement
  // that camera aligned to the view's photograph with the model fixed.
  Camera scoring_camera(const DatasetView& view) const;

  int iteration() const { return iteration_; }  // iterations completed
  int active_sh_degree() const { return active_sh_degree_; }
  const GaussianModel& model() const { return model_; }
  // The gradient the last step gave Adam: its view's, or the mean of its batch's (with any
  // regulariser the strategy added).
  const GaussianModel& last_step_gradient() const { return *last_step_gradient_; }
  // The parameters as of the last check that found every group finite.
  const GaussianModel& last_good_model() const { return last_good_model_; }
  const SplatTrainingConfig& config() const { return config_; }
  float scene_extent() const { return scene_extent_; }
  const InitialisationReport& initialisation() const { return initialisation_; }
  const DensityStrategy& strategy() const { return *strategy_; }
  // Pose refinement's corrections of the training views (none without refine_poses).
  const PoseRefiner& pose_refiner() const { return pose_refiner_; }
  // The training views' cameras as trained: the recorded ones, corrected under refine_poses.
  std::vector<Camera> training_cameras() const;
  const ExposureCompensation& exposure_compensation() const { return exposure_; }

  // The fraction of the run's time budget spent so far (the training loop sets it before
  // each step when there is a budget); schedules that follow the budget read it.
  void set_time_budget_fraction(double fraction) { time_budget_fraction_ = fraction; }

  // Shares each step's views with the other ranks of `group` (data-parallel training; null
  // or a group of one: this process takes them all). Every rank must hold the same trainer
  // state; each then renders its block of batch / ranks views and all take the same step.
  // ArgumentError unless batch / ranks is a whole power of two (view_batch.hpp: what makes
  // the model independent of the number of ranks).
  void set_process_group(ProcessGroup* group);

  // Throws TrainingDiverged naming the first parameter group with a non-finite value.
  void check_parameters_finite() const;
  // Fault injection for the tests of the divergence path (settings within their limits no
  // longer make training diverge): sets one mean to NaN.
  void inject_non_finite_parameter() { model_.means.at(0) = std::nanf(""); }

  // Everything needed to continue exactly where training stopped (model, Adam state,
  // densification statistics, random state, view order), written atomically.
  void save_checkpoint(const std::filesystem::path& file) const;
  // Restores a checkpoint written by save_checkpoint; throws InputError naming the file if it
  // is not one or was written for different data.
  void load_checkpoint(const std::filesystem::path& file);

 private:
  std::size_t next_view();
  // The training image of view `view` at 1/divisor of its size (built once, then kept).
  const Image& training_image(std::size_t view, int divisor);
  GroupLearningRates learning_rates() const;
  // Adam's decays: the official 0.9 / 0.999, raised to the batch's size.
  AdamSettings adam_settings() const;
  PoseLearningRates pose_learning_rates() const;
  // The pivot of `camera`'s pose correction: the depth of the scene's centre in front of it
  // under pose_pivot_at_scene (0 if behind it), else 0 (the camera centre).
  float pose_pivot_depth(const Camera& camera) const;
  // The training views' corrections at the identity, each with its pivot.
  PoseRefiner new_pose_refiner() const;
  RenderSettings render_settings() const;
  // How far the run's schedules (position step, growth and pruning phases) have advanced, in
  // the schedule's iterations: `iteration` itself, or under schedule_follows_budget the
  // iteration scaled from schedule_iterations to position_lr_max_steps, or the spent fraction
  // of the time budget × position_lr_max_steps when that is further along.
  double schedule_iteration(int iteration) const;

  const Dataset& dataset_;
  SplatTrainingConfig config_;
  float scene_extent_;
  InitialisationReport initialisation_;  // before model_: initial_model fills it
  GaussianModel model_, last_good_model_;
  FarSteps far_steps_;                     // off unless the start was random
  std::vector<float> means_before_step_;   // what scale_far_steps measures the step from
  AdamState adam_;
  std::unique_ptr<DensityStrategy> strategy_;
  std::mt19937 rng_;
  std::vector<std::size_t> view_stack_;  // training views not yet used in this epoch
  int iteration_ = 0;
  int active_sh_degree_ = 0;
  double time_budget_fraction_ = 0;

  Rasterizer rasterizer_;
  RenderResult render_;
  RasterGradients grads_;
  // One step's batch (config_.batch views): which views, each one's statistics for the
  // density strategy, and the pairwise sum of their gradients (view_batch.hpp); over several
  // ranks, what they send each other (batch_exchange.hpp).
  ProcessGroup* group_ = nullptr;  // null: this process takes every view
  BatchExchange exchange_;
  std::vector<std::size_t> batch_views_;
  std::vector<ViewStatistics> view_stats_;
  std::vector<BackwardStats> backward_stats_;  // views of view_stats_
  PairwiseGradientSum batch_gradient_;
  const GaussianModel* last_step_gradient_ = &grads_.params;
  Image v_image_;
  SsimScratch ssim_scratch_;
  std::vector<std::vector<Image>> reduced_images_;  // [divisor][view], empty until needed
  glm::vec3 scene_centre_{0.0f};                   // the point cloud's median, else the cameras' mean
  PoseRefiner pose_refiner_;                        // [train view] under refine_poses
  std::vector<Camera> recorded_training_cameras_;   // [train view] under refine_poses
  ExposureCompensation exposure_;                   // [train view] under exposure_compensation
  Image compensated_;                               // the render through the view's map
};

}  // namespace splat
