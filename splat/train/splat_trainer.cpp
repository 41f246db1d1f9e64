#include "splat/train/splat_trainer.hpp"

#include <algorithm>
#include <chrono>
#include <limits>
#include <cmath>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include "splat/core/settings_table.hpp"
#include "splat/data/resample.hpp"
#include "splat/optim/lr_schedule.hpp"
#include "splat/optim/step_events.hpp"
#include "splat/train/training_support.hpp"

namespace splat {

namespace {

// The compact strategy's warm-up; the official recipe trains at full size throughout.
ResolutionSchedule make_resolution_schedule(const SplatTrainingConfig& config, const Dataset& dataset) {
  if (config.strategy != "compact") return {};
  const CompactSettings& c = config.compact;
  // Never below kMinSide pixels on an image's short side: smaller images hold too little to
  // learn from (the loss's 11-pixel SSIM window hardly fits). At 32 pixels the 200-pixel
  // views of scenes/shiny started at 1/6 and ended 0.14 dB lower at 7,000 iterations than
  // from 1/3 (bench/HISTORY.md, issue 39).
  constexpr int kMinSide = 64;
  int short_side = std::numeric_limits<int>::max();
  for (const DatasetView& view : dataset.train)
    short_side = std::min({short_side, view.image.width, view.image.height});
  const ResolutionScheduleSettings settings{
      c.warmup_by_spectrum ? ResolutionShape::kSpectrum : ResolutionShape::kHalving,
      std::clamp(short_side / kMinSide, 1, std::max(1, c.warmup_divisor)), c.warmup_until};
  // The spectrum of a few views spread over the training set stands for all of them.
  constexpr std::size_t kSpectrumViews = 16;
  std::vector<const Image*> images;
  const std::size_t views = dataset.train.size();
  const std::size_t count = std::min(views, kSpectrumViews);
  if (settings.shape == ResolutionShape::kSpectrum)
    for (std::size_t i = 0; i < count; ++i) images.push_back(&dataset.train[i * views / count].image);
  return ResolutionSchedule(settings, images);
}

Image clamped(const Image& image) {
  Image out = image;
  for (float& v : out.data) v = std::clamp(v, 0.0f, 1.0f);
  return out;
}

}  // namespace

using training::all_finite;
using training::Clock;
using training::kLastGoodInterval;
using training::ms_since;

SplatTrainer::SplatTrainer(const Dataset& dataset, const SplatTrainingConfig& config)
    : dataset_(dataset),
      config_(validated(config)),
      scene_extent_(dataset.scene_extent),
      model_(initial_model(dataset, config, &initialisation_)),
      rng_(config.seed) {
  // Only where the scene may reach any distance and its far content starts at random depths
  // (initial_model.hpp, "frusta"): a point cloud starts far content at its depth, and an
  // object in a cube has none.
  if (initialisation_.kind == "frusta")
    far_steps_ = {initialisation_.centre, initialisation_.distance, initialisation_.far,
                  config_.far_position_step_exponent};
  if (dataset.train.empty()) throw ArgumentError("training needs at least one training view");
  if (config_.schedule_iterations == 0) config_.schedule_iterations = config_.iterations;
  config_.density.white_background =
      config.background[0] == 1.0f && config.background[1] == 1.0f && config.background[2] == 1.0f;
  strategy_ = make_density_strategy(config_, dataset, model_.size());
  resolution_ = make_resolution_schedule(config_, dataset);
  adam_.reset_like(model_);
  last_good_model_ = model_;
  corrections_ = ViewCorrections(dataset, config_, scene_extent_);
  holdout_ = ValidationHoldout(dataset, config_.validation);
}

std::size_t SplatTrainer::next_view() {
  // As the official trainer: a random permutation of the training views, consumed one per
  // iteration and refilled when empty (without the views the validation holdout keeps).
  if (view_stack_.empty())
    for (std::size_t i = 0; i < dataset_.train.size(); ++i)
      if (!holdout_.holds_out(i)) view_stack_.push_back(i);
  std::uniform_int_distribution<std::size_t> pick(0, view_stack_.size() - 1);
  const std::size_t slot = pick(rng_);
  const std::size_t view = view_stack_[slot];
  view_stack_.erase(view_stack_.begin() + std::ptrdiff_t(slot));
  return view;
}

namespace {

// `full` (view `view` of `views` views) at 1/divisor of its size, from `cache` ([divisor][view])
// or made and kept there.
const Image& reduced_image(const Image& full, std::size_t view, std::size_t views, int divisor,
                           std::vector<std::vector<Image>>& cache) {
  if (divisor <= 1) return full;
  if (cache.size() <= std::size_t(divisor)) cache.resize(std::size_t(divisor) + 1);
  std::vector<Image>& images = cache[std::size_t(divisor)];
  if (images.empty()) images.resize(views);
  Image& reduced = images[view];
  if (reduced.width == 0)
    reduced = resample_area(full, std::max(1, full.width / divisor), std::max(1, full.height / divisor));
  return reduced;
}

}  // namespace

const Image& SplatTrainer::training_image(std::size_t view, int divisor) {
  return reduced_image(dataset_.train[view].image, view, dataset_.train.size(), divisor, reduced_images_);
}

const Image* SplatTrainer::training_mask(std::size_t view, int divisor) {
  const Image& full = dataset_.train[view].mask;
  if (full.empty()) return nullptr;
  return &reduced_image(full, view, dataset_.train.size(), divisor, reduced_masks_);
}

double SplatTrainer::schedule_iteration(int iteration) const {
  return splat::schedule_iteration(config_, iteration, time_budget_fraction_);
}

GroupLearningRates SplatTrainer::learning_rates() const {
  ExponentialLrSchedule position{config_.position_lr_init * scene_extent_,
                                 config_.position_lr_final * scene_extent_,
                                 config_.position_lr_max_steps};
  GroupLearningRates lr;
  // The official evaluates it at the 1-based iteration.
  const double iteration = schedule_iteration(iteration_ + 1);
  lr.means = float(position.at_fraction(iteration / double(config_.position_lr_max_steps)));
  const float appearance = appearance_lr_factor(config_, iteration);
  lr.sh_dc = config_.sh_dc_lr * appearance;
  lr.sh_rest = config_.sh_rest_lr * appearance;
  lr.opacity = config_.opacity_lr * appearance;
  lr.scales = config_.scale_lr * appearance;
  lr.rotations = config_.rotation_lr * appearance;
  if (config_.batch > 1) {
    // A batch of B views averages B gradients, so its steps can be longer. Grendel-GS
    // (Zhao et al. 2024, "On Scaling Up 3D Gaussian Splatting Training") multiplies Adam's
    // rates by √B (batch_lr_exponent 0.5) and raises the moments' decays to the B-th power
    // (adam_settings); the default here is B (exponent 1), which measured better.
    lr.multiply(float(std::pow(double(config_.batch), double(config_.batch_lr_exponent))));
  }
  return lr;
}

AdamSettings SplatTrainer::adam_settings() const {
  AdamSettings settings;
  // One step of a batch of B stands for B steps of one view: the moments forget as much.
  settings.beta1 = std::pow(settings.beta1, double(config_.batch));
  settings.beta2 = std::pow(settings.beta2, double(config_.batch));
  settings.average_decay = std::pow(double(config_.parameter_average_decay), double(config_.batch));
  return settings;
}

RenderSettings SplatTrainer::render_settings() const {
  RenderSettings settings;
  settings.sh_degree = active_sh_degree_;
  std::copy(config_.background, config_.background + 3, settings.background);
  settings.alpha_clamp_gradient = config_.alpha_clamp_gradient;
  return settings;
}

StepResult SplatTrainer::step() {
  const int views = config_.batch;
  const int iteration = iteration_ + views;  // the step's last view, 1-based as train.py counts
  StepResult result;
  if (step_reaches_multiple(iteration, views, config_.sh_increase_interval))
    active_sh_degree_ = std::min(active_sh_degree_ + 1, model_.sh_degree);
  batch_views_.clear();
  for (int v = 0; v < views; ++v) batch_views_.push_back(next_view());
  const int phase = int(schedule_iteration(iteration));
  result.resolution_divisor = resolution_.divisor(phase);
  const Camera recorded = differentiate_views(iteration, result.resolution_divisor, result);

  auto start = Clock::now();
  const ReducedBatch batch = batch_.reduce(view_step_);
  last_step_gradient_ = &batch.gradient;
  result.loss = batch.loss.loss;
  result.l1 = batch.loss.l1;
  result.ssim = batch.loss.ssim;
  result.exchange = batch.exchange;
  if (!std::isfinite(result.loss)) throw TrainingDiverged(iteration, "loss");
  if (batch_.ranks() > 1) result.timings.exchange = ms_since(start);

  start = Clock::now();
  // The run's last iteration only gathers statistics (see DensityStrategy). Extending a
  // finished run with --resume and more iterations therefore misses that one decision.
  TrainingState state{model_, adam_, rng_, scene_extent_, phase, result.resolution_divisor};
  result.density = strategy_->step_post_backward(iteration, iteration == config_.iterations, state, batch.gradient,
                                                 batch.views);
  result.timings.densify = ms_since(start);

  start = Clock::now();
  const GroupLearningRates lr = learning_rates();
  step_model(batch, result.density, lr);
  if (corrections_.refines_poses_at(iteration))
    corrections_.step_pose(batch_views_.back(), recorded, view_step_.gradients().camera_pose,
                           schedule_iteration(iteration_ + 1));
  strategy_->step_post_optimizer(iteration, state, lr.means);
  check_step_finite(iteration);
  result.timings.optimizer = ms_since(start);
  iteration_ = iteration;
  validate_if_due();
  return result;
}

void SplatTrainer::validate_if_due() {
  // Point N is scored before the step that holds iteration N, as the test points are (see
  // train_command.cpp): scored after it, the opacity resets at multiples of 3,000 gave real_cup
  // validation scores of 8 dB among 27–30.
  if (!holdout_.due(iteration_ + config_.batch, config_.batch)) return;
  const double psnr = evaluate(holdout_.views(), nullptr, Measures::kPsnrOnly).psnr;
  const double fraction = schedule_iteration(iteration_) / double(config_.position_lr_max_steps);
  if (holdout_.record(iteration_, psnr, model_, fraction) != ValidationHoldout::Decision::kRestore) return;
  // Training ends on the best model. Its optimiser state and density statistics start afresh,
  // so that a checkpoint of it is consistent; nothing trains on it any more (finished()).
  model_ = holdout_.best_model();
  adam_.reset_like(model_);
  strategy_ = make_density_strategy(config_, dataset_, model_.size());
  last_good_model_ = model_;
}

Camera SplatTrainer::differentiate_views(int iteration, int resolution_divisor, StepResult& result) {
  ViewStepSettings settings;
  settings.render = render_settings();
  settings.ssim_weight = config_.ssim_weight;
  settings.camera_pose_gradient = corrections_.refines_poses_at(iteration);
  // One view's SH gradient is rank one: Adam forms its rows from 6 floats a Gaussian. A
  // batch sums several views' rows, which needs them whole.
  settings.sh_gradient_factors = config_.batch == 1;
  // Over several ranks a non-finite loss shows in the batch's, which every rank sees.
  settings.stop_on_non_finite_loss = batch_.ranks() == 1;
  batch_.start(config_.batch);
  Camera recorded;
  for (int v = batch_.first(); v < batch_.first() + batch_.count(); ++v) {
    const std::size_t view = batch_views_[std::size_t(v)];
    const Image& target = training_image(view, resolution_divisor);
    recorded = resolution_divisor == 1 ? dataset_.train[view].camera
                                       : dataset_.train[view].camera.resized(target.width, target.height);
    const ViewStepResult step =
        view_step_.run(model_, corrections_.camera(view, recorded), target, settings,
                       corrections_.exposure(view, iteration, schedule_iteration(iteration)),
                       training_mask(view, resolution_divisor));
    result.timings += step.timings;
    if (!step.differentiated) throw TrainingDiverged(iteration, "loss");
    batch_.add(v, step.loss, view_step_);
  }
  return recorded;
}

void SplatTrainer::step_model(const ReducedBatch& batch, const DensityStepReport& density,
                              const GroupLearningRates& lr) {
  // After densification every parameter array is new and has no gradient in the official
  // trainer, so its optimiser skips the step; after an opacity reset only the opacities do.
  // (train.py also skips the last iteration's step; we take it, so that a run resumed from
  // a checkpoint is identical to one that never stopped.)
  if (density.densified) return;
  AdamGroupMask active;
  active.opacity = !density.opacity_reset;
  // The bands above the active degree have had no gradient yet (none is rendered with them).
  active.sh_degree = active_sh_degree_;
  if (config_.parameter_average_decay > 0 && !adam_.averaging() &&
      schedule_iteration(iteration_ + 1) >= config_.parameter_average_from * config_.position_lr_max_steps)
    adam_.start_average(model_, iteration_);
  if (far_steps_.active()) means_before_step_ = model_.means;
  adam_step(model_, batch.gradient, adam_, lr, adam_settings(), active, batch.sh_factors);
  if (far_steps_.active()) scale_far_steps(model_.means, means_before_step_, far_steps_);
}

void SplatTrainer::check_step_finite(int iteration) {
  for (const ParameterGroup& group : kParameterGroups)
    if (group.id != ParameterGroupId::kSh && !all_finite(group.of(model_))) throw TrainingDiverged(iteration, group.name);
  if (step_reaches_multiple(iteration, config_.batch, kLastGoodInterval)) {
    const ParameterGroup& sh = parameter_group(ParameterGroupId::kSh);
    if (!all_finite(sh.of(model_))) throw TrainingDiverged(iteration, sh.name);
    last_good_model_ = model_;
  }
}

void SplatTrainer::set_process_group(ProcessGroup* group) { batch_.set_process_group(group, config_.batch); }

void SplatTrainer::check_parameters_finite() const {
  for (const ParameterGroup& group : kParameterGroups)
    if (!all_finite(group.of(model_))) throw TrainingDiverged(iteration_, group.name);
}

const GaussianModel& SplatTrainer::output_model() const {
  if (!adam_.averaging()) return model_;
  if (averaged_model_iteration_ != iteration_) {
    averaged_model_ = adam_.averaged(model_);
    averaged_model_iteration_ = iteration_;
  }
  return averaged_model_;
}

Image SplatTrainer::render(const Camera& camera) const {
  Rasterizer rasterizer;
  RenderResult result;
  RenderSettings settings = render_settings();
  settings.for_backward = false;  // a render to look at or score
  rasterizer.render(output_model(), camera, settings, result);
  return clamped(result.color);
}

Camera SplatTrainer::scoring_camera(const DatasetView& view) const {
  return corrections_.scoring_camera(output_model(), view, render_settings());
}

std::optional<double> SplatTrainer::test_psnr_at_recorded_poses() const {
  if (dataset_.test.empty()) return std::nullopt;
  const FrameChange frame = corrections_.frame_change();
  return score_views(
             dataset_.test, [&](const DatasetView& view) { return frame.applied_to(view.camera); },
             [&](const Camera& camera) { return render(camera); }, nullptr, Measures::kPsnrOnly)
      .psnr;
}

Evaluation SplatTrainer::evaluate(const std::vector<DatasetView>& views, std::vector<Image>* renders,
                                  Measures measures) {
  // Under pose refinement the scene's frame has moved with the training poses: each view is
  // first aligned to its photograph with the model fixed, from its recorded pose every time
  // (so a score depends only on the model, and a resumed run scores as an uninterrupted one).
  return score_views(
      views, [&](const DatasetView& view) { return scoring_camera(view); },
      [&](const Camera& camera) { return render(camera); }, renders, measures);
}

}  // namespace splat
