#pragma once
// The Gaussian-splatting trainer: the official 3DGS optimisation loop on the CPU rasterizer.
// One step() is one iteration, or one per view of a batch: pick the views, render, score and
// differentiate each (ViewStep), reduce the batch (BatchReduction, over the ranks of a
// data-parallel run), density control (the configured DensityStrategy's hooks), Adam, and the
// views' pose and exposure corrections (ViewCorrections). No printing: the command line
// reports progress.
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "splat/data/dataset.hpp"
#include "splat/optim/adam.hpp"
#include "splat/optim/far_steps.hpp"
#include "splat/raster/rasterizer.hpp"
#include "splat/train/batch_reduction.hpp"
#include "splat/train/density_strategy.hpp"
#include "splat/train/evaluation.hpp"
#include "splat/train/initial_model.hpp"
#include "splat/train/process_group.hpp"
#include "splat/train/resolution_schedule.hpp"
#include "splat/train/step_result.hpp"
#include "splat/train/training_config.hpp"
#include "splat/train/validation_holdout.hpp"
#include "splat/train/view_corrections.hpp"
#include "splat/train/view_step.hpp"
#include "splat/train/resume_settings.hpp"

namespace splat {

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
  Evaluation evaluate(const std::vector<DatasetView>& views, std::vector<Image>* renders = nullptr,
                      Measures measures = Measures::kAll);
  // The image evaluate() scores for one camera (clamped to [0, 1]), without scoring it: what
  // splat-eval times as the render cost.
  Image render(const Camera& camera) const;
  // The camera evaluate() renders `view` with: its recorded one, or under pose refinement
  // that camera aligned to the view's photograph with the model fixed.
  Camera scoring_camera(const DatasetView& view) const;
  // Under pose refinement, the mean PSNR of the dataset's test views at their recorded poses
  // carried into the model's frame, without the alignment evaluate() gives each: how well the
  // model still fits the poses the photographs came with (metrics.json's pose_refinement).
  // None without test views.
  std::optional<double> test_psnr_at_recorded_poses() const;

  int iteration() const { return iteration_; }  // iterations completed
  // Whether training has ended by its own decision: the validation holdout found the model
  // fallen and restored its best one (validation_holdout.hpp). step() must not be called then.
  bool finished() const { return holdout_.restored(); }
  const ValidationHoldout& validation() const { return holdout_; }
  int active_sh_degree() const { return active_sh_degree_; }
  // The parameters Adam steps (the iterate).
  const GaussianModel& model() const { return model_; }
  // The model the run scores, renders and saves: the parameter average once one is kept
  // (parameter_average_decay), otherwise the parameters themselves.
  const GaussianModel& output_model() const;
  // The iteration the parameter average started at (none while there is none).
  std::optional<int> parameter_average_start() const { return adam_.average_start; }
  // The gradient the last step gave Adam: the mean of its batch's (with any regulariser the
  // strategy added). A batch of one view gives Adam its SH gradient in factored form
  // (sh_gradient_factors.hpp): then this model's SH rows are not that gradient.
  const GaussianModel& last_step_gradient() const { return *last_step_gradient_; }
  // The parameters as of the last check that found every group finite.
  const GaussianModel& last_good_model() const { return last_good_model_; }
  const SplatTrainingConfig& config() const { return config_; }
  float scene_extent() const { return scene_extent_; }
  const InitialisationReport& initialisation() const { return initialisation_; }
  const ResolutionSchedule& resolution_schedule() const { return resolution_; }
  const DensityStrategy& strategy() const { return *strategy_; }
  // Pose refinement's corrections of the training views (none without refine_poses).
  const PoseRefiner& pose_refiner() const { return corrections_.pose_refiner(); }
  // The training views' cameras as trained: the recorded ones, corrected under refine_poses.
  std::vector<Camera> training_cameras() const { return corrections_.training_cameras(); }
  const ExposureCompensation& exposure_compensation() const { return corrections_.exposure_compensation(); }

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
  // Restores a checkpoint written by save_checkpoint, with the settings it was written with
  // but the limits and intervals `given` (resume_settings.hpp); throws InputError naming the
  // file if it is not one, was written for different data, or `given` changes its settings.
  void load_checkpoint(const std::filesystem::path& file, const GivenSettings& given = {});

 private:
  std::size_t next_view();
  // The training image of view `view` at 1/divisor of its size, and its mask at that size
  // (null when the view has none); each built once, then kept.
  const Image& training_image(std::size_t view, int divisor);
  const Image* training_mask(std::size_t view, int divisor);
  GroupLearningRates learning_rates() const;
  // Adam's decays: the official 0.9 / 0.999, raised to the batch's size.
  AdamSettings adam_settings() const;
  RenderSettings render_settings() const;
  // How far the run's schedules (position step, growth and pruning phases) have advanced, in
  // the schedule's iterations: `iteration` itself, or under schedule_follows_budget the
  // iteration scaled from schedule_iterations to position_lr_max_steps, or the spent fraction
  // of the time budget × position_lr_max_steps when that is further along.
  double schedule_iteration(int iteration) const;

  // The parts of a step at `iteration` (its last view's), in order.
  // Renders, scores and differentiates this process's views of the batch (all of them, or
  // its rank's block), each joining batch_. Returns the (last) view's recorded camera at the
  // size trained on, which a pose step starts from (batch 1 only).
  Camera differentiate_views(int iteration, int resolution_divisor, StepResult& result);
  // Adam on the model, skipped after density control changed the rows, its opacity group
  // skipped after an opacity reset; far content's steps scaled.
  void step_model(const ReducedBatch& batch, const DensityStepReport& density, const GroupLearningRates& lr);
  // TrainingDiverged naming the first non-finite group: the cheap groups every step, the SH
  // coefficients (most of the data) every kLastGoodInterval iterations, when the parameters
  // are also kept as the last good ones.
  void check_step_finite(int iteration);
  // At the holdout's scoring points: scores its views, and carries out its decision.
  void validate_if_due();

  const Dataset& dataset_;
  // views_fingerprint of the training views as 16 hex digits, computed at the first checkpoint.
  std::string train_images_fingerprint() const;
  mutable std::string train_images_fingerprint_;
  SplatTrainingConfig config_;
  float scene_extent_;
  InitialisationReport initialisation_;  // before model_: initial_model fills it
  GaussianModel model_, last_good_model_;
  FarSteps far_steps_;                     // off unless the start was random
  std::vector<float> means_before_step_;   // what scale_far_steps measures the step from
  AdamState adam_;
  // output_model()'s average, formed when first asked for after a step.
  mutable GaussianModel averaged_model_;
  mutable std::optional<int> averaged_model_iteration_;
  std::unique_ptr<DensityStrategy> strategy_;
  ResolutionSchedule resolution_;
  std::mt19937 rng_;
  std::vector<std::size_t> view_stack_;  // training views not yet used in this epoch
  int iteration_ = 0;
  int active_sh_degree_ = 0;
  double time_budget_fraction_ = 0;
  std::vector<std::vector<Image>> reduced_images_;  // [divisor][view], empty until needed
  std::vector<std::vector<Image>> reduced_masks_;   // the same for the views' masks

  std::vector<std::size_t> batch_views_;  // the step's views, in batch order
  ViewStep view_step_;                    // one view's render, loss and backward
  BatchReduction batch_;                  // the step's views' gradients and statistics
  const GaussianModel* last_step_gradient_ = &view_step_.gradients().params;
  ViewCorrections corrections_;           // [train view] poses and exposure maps
  ValidationHoldout holdout_;             // training views held out while the model grows
};

}  // namespace splat
