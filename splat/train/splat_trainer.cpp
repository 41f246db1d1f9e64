#include "splat/train/splat_trainer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include "splat/core/frame_change.hpp"
#include "splat/core/settings_table.hpp"
#include "splat/data/resample.hpp"
#include "splat/optim/lr_schedule.hpp"
#include "splat/optim/step_events.hpp"
#include "splat/train/training_support.hpp"

namespace splat {

namespace {

// Where the scene is: the median of the point cloud per axis (robust to stray points), or
// without one the mean of the training cameras' centres (the middle of a capture around it).
glm::vec3 scene_centre(const Dataset& dataset) {
  if (dataset.points && dataset.points->size() > 0) {
    std::vector<float> axis(dataset.points->size());
    glm::vec3 median;
    for (int a = 0; a < 3; ++a) {
      for (std::size_t i = 0; i < axis.size(); ++i) axis[i] = dataset.points->positions[3 * i + a];
      std::nth_element(axis.begin(), axis.begin() + axis.size() / 2, axis.end());
      median[a] = axis[axis.size() / 2];
    }
    return median;
  }
  return mean_camera_centre(dataset.train);
}

using training::all_finite;
using training::Clock;
using training::kLastGoodInterval;
using training::ms_since;

Image clamped(const Image& image) {
  Image out = image;
  for (float& v : out.data) v = std::clamp(v, 0.0f, 1.0f);
  return out;
}

}  // namespace

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
  strategy_ = make_density_strategy(config_, dataset.train.size(), model_.size());
  adam_.reset_like(model_);
  last_good_model_ = model_;
  if (config_.refine_poses) {
    scene_centre_ = scene_centre(dataset);
    pose_refiner_ = new_pose_refiner();
    recorded_training_cameras_ = cameras_of(dataset_.train);
  }
  if (config_.exposure_compensation) {
    exposure_ = ExposureCompensation(dataset.train.size());
  }
}

std::size_t SplatTrainer::next_view() {
  // As the official trainer: a random permutation of the training views, consumed one per
  // iteration and refilled when empty.
  if (view_stack_.empty())
    for (std::size_t i = 0; i < dataset_.train.size(); ++i) view_stack_.push_back(i);
  std::uniform_int_distribution<std::size_t> pick(0, view_stack_.size() - 1);
  const std::size_t slot = pick(rng_);
  const std::size_t view = view_stack_[slot];
  view_stack_.erase(view_stack_.begin() + std::ptrdiff_t(slot));
  return view;
}

const Image& SplatTrainer::training_image(std::size_t view, int divisor) {
  const Image& full = dataset_.train[view].image;
  if (divisor <= 1) return full;
  if (reduced_images_.size() <= std::size_t(divisor)) reduced_images_.resize(std::size_t(divisor) + 1);
  std::vector<Image>& images = reduced_images_[std::size_t(divisor)];
  if (images.empty()) images.resize(dataset_.train.size());
  Image& reduced = images[view];
  if (reduced.width == 0)
    reduced = resample_area(full, std::max(1, full.width / divisor), std::max(1, full.height / divisor));
  return reduced;
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
    const float scale = float(std::pow(double(config_.batch), double(config_.batch_lr_exponent)));
    for (float* rate : {&lr.means, &lr.sh_dc, &lr.sh_rest, &lr.opacity, &lr.scales, &lr.rotations}) *rate *= scale;
  }
  return lr;
}

AdamSettings SplatTrainer::adam_settings() const {
  AdamSettings settings;
  // One step of a batch of B stands for B steps of one view: the moments forget as much.
  settings.beta1 = std::pow(settings.beta1, double(config_.batch));
  settings.beta2 = std::pow(settings.beta2, double(config_.batch));
  return settings;
}

PoseLearningRates SplatTrainer::pose_learning_rates() const {
  const double fraction =
      schedule_iteration(iteration_ + 1) / double(config_.position_lr_max_steps) / config_.pose_lr_decay_until;
  const auto decayed = [&](float lr) {
    if (lr == 0.0f) return 0.0f;
    return float(ExponentialLrSchedule{lr, lr * config_.pose_lr_final_factor, 1}.at_fraction(std::min(1.0, fraction)));
  };
  return {decayed(config_.pose_rotation_lr), decayed(config_.pose_translation_lr)};
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
  result.resolution_divisor = strategy_->resolution_divisor(iteration);
  const RenderSettings settings = render_settings();
  grads_.with_camera_pose = config_.refine_poses && iteration >= config_.pose_refine_from;

  // Each of this process's views (all of them, or its rank's block): render, loss, backward;
  // its gradient joins the pairwise sum and its statistics are kept for the density strategy.
  const int ranks = group_ ? group_->size() : 1;
  const int per_rank = views / ranks;
  const int first = group_ ? group_->rank() * per_rank : 0;
  batch_gradient_.clear();
  view_stats_.resize(std::size_t(views));
  Camera recorded, camera;  // the (last) view's, for pose refinement (batch 1 only)
  for (int v = first; v < first + per_rank; ++v) {
    const std::size_t view = batch_views_[std::size_t(v)];
    const Image& target = training_image(view, result.resolution_divisor);
    recorded = result.resolution_divisor == 1 ? dataset_.train[view].camera
                                              : dataset_.train[view].camera.resized(target.width, target.height);
    camera = config_.refine_poses ? pose_refiner_.camera(view, recorded) : recorded;

    auto start = Clock::now();
    rasterizer_.render(model_, camera, settings, render_);
    result.timings.forward += ms_since(start);
    result.timings.project += rasterizer_.last_timings().project_ms;
    result.timings.bin_sort += rasterizer_.last_timings().bin_sort_ms;
    result.timings.blend += rasterizer_.last_timings().blend_ms;

    start = Clock::now();
    const bool compensate = config_.exposure_compensation && iteration >= config_.exposure_from;
    if (compensate) exposure_.apply(view, render_.color, compensated_);
    const LossValue loss = photometric_loss(compensate ? compensated_ : render_.color, target, config_.ssim_weight,
                                            &v_image_, ssim_scratch_);
    if (compensate)
      exposure_.backward_and_step(view, render_.color, v_image_,
                                  config_.exposure_lr * appearance_lr_factor(config_, schedule_iteration(iteration)));
    result.timings.loss += ms_since(start);
    ViewStatistics& stats = view_stats_[std::size_t(v)];
    stats.loss = loss;
    if (ranks == 1 && !std::isfinite(loss.loss)) throw TrainingDiverged(iteration, "loss");

    start = Clock::now();
    rasterizer_.backward(model_, camera, settings, render_, v_image_, grads_);
    if (views > 1) {  // kept until the batch ends; a single view's are read where they are
      batch_gradient_.take(grads_.params);
      stats.viewspace_grad_norm = grads_.viewspace_grad_norm;
      stats.radii = render_.frame.projected.radius;
      stats.blend_weight = grads_.blend_weight;
      stats.width = camera.width;
      stats.height = camera.height;
    }
    result.timings.backward += ms_since(start);
    result.timings.blend_backward += rasterizer_.last_timings().blend_backward_ms;
    result.timings.project_backward += rasterizer_.last_timings().project_backward_ms;
  }

  auto start = Clock::now();
  // The mean loss's gradient: the views' sum over the batch (a single view's as it is).
  GaussianModel* grads = &grads_.params;
  if (views > 1) {
    if (ranks > 1) {
      grads = &exchange_.exchange(*group_, batch_gradient_.total(), view_stats_);
      result.exchange = exchange_.last_report();
    } else {
      grads = &batch_gradient_.total();
    }
    grads->scale(1.0f / float(views));
  }
  last_step_gradient_ = grads;
  for (const ViewStatistics& stats : view_stats_) {
    result.loss += stats.loss.loss / views;
    result.l1 += stats.loss.l1 / views;
    result.ssim += stats.loss.ssim / views;
  }
  if (!std::isfinite(result.loss)) throw TrainingDiverged(iteration, "loss");
  if (ranks > 1) result.timings.exchange = ms_since(start);

  start = Clock::now();
  // The run's last iteration only gathers statistics (see DensityStrategy). Extending a
  // finished run with --resume and more iterations therefore misses that one decision.
  TrainingState state{model_, adam_, rng_, scene_extent_, int(schedule_iteration(iteration))};
  backward_stats_.clear();
  if (views == 1)
    backward_stats_.push_back({grads_.viewspace_grad_norm, render_.frame.projected.radius, grads_.blend_weight,
                               camera.width, camera.height});
  else
    for (const ViewStatistics& v : view_stats_)
      backward_stats_.push_back({v.viewspace_grad_norm, v.radii, v.blend_weight, v.width, v.height});
  result.density = strategy_->step_post_backward(iteration, iteration == config_.iterations, state, *grads,
                                                 backward_stats_);
  result.timings.densify = ms_since(start);

  start = Clock::now();
  // After densification every parameter array is new and has no gradient in the official
  // trainer, so its optimiser skips the step; after an opacity reset only the opacities do.
  // (train.py also skips the last iteration's step; we take it, so that a run resumed from
  // a checkpoint is identical to one that never stopped.)
  const GroupLearningRates lr = learning_rates();
  if (!result.density.densified) {
    AdamGroupMask active;
    active.opacity = !result.density.opacity_reset;
    if (far_steps_.active()) means_before_step_ = model_.means;
    adam_step(model_, *grads, adam_, lr, adam_settings(), active);
    if (far_steps_.active()) scale_far_steps(model_.means, means_before_step_, far_steps_);
  }
  if (grads_.with_camera_pose) {
    pose_refiner_.step(batch_views_.back(), recorded, grads_.camera_pose, pose_learning_rates());
    if (config_.pose_hold_frame) pose_refiner_.hold_frame(recorded_training_cameras_);
  }
  strategy_->step_post_optimizer(iteration, state, lr.means);
  // The cheap groups every iteration; SH coefficients (most of the data) less often: a NaN
  // there shows in the next loss anyway.
  const std::pair<const char*, const std::vector<float>*> groups[] = {
      {"means", &model_.means}, {"log_scales", &model_.log_scales}, {"quaternions", &model_.quats},
      {"opacity_logits", &model_.opacity_logits}};
  for (const auto& [name, values] : groups)
    if (!all_finite(*values)) throw TrainingDiverged(iteration, name);
  if (step_reaches_multiple(iteration, views, kLastGoodInterval)) {
    if (!all_finite(model_.sh)) throw TrainingDiverged(iteration, "sh_coefficients");
    last_good_model_ = model_;
  }
  result.timings.optimizer = ms_since(start);
  iteration_ = iteration;
  return result;
}

void SplatTrainer::set_process_group(ProcessGroup* group) {
  if (group && group->size() > 1) {
    const int ranks = group->size(), views = config_.batch;
    if (views % ranks != 0 || ((views / ranks) & (views / ranks - 1)) != 0)
      throw ArgumentError("--batch " + std::to_string(views) + " over " + std::to_string(ranks) +
                          " ranks: each rank takes batch / ranks views, which must be a whole power of two "
                          "(1, 2, 4, ...) so that the model does not depend on the number of ranks");
  }
  group_ = group && group->size() > 1 ? group : nullptr;
}

void SplatTrainer::check_parameters_finite() const {
  const std::pair<const char*, const std::vector<float>*> groups[] = {
      {"means", &model_.means},
      {"log_scales", &model_.log_scales},
      {"quaternions", &model_.quats},
      {"opacity_logits", &model_.opacity_logits},
      {"sh_coefficients", &model_.sh}};
  for (const auto& [name, values] : groups)
    if (!all_finite(*values)) throw TrainingDiverged(iteration_, name);
}

Image SplatTrainer::render(const Camera& camera) const {
  Rasterizer rasterizer;
  RenderResult result;
  rasterizer.render(model_, camera, render_settings(), result);
  return clamped(result.color);
}

std::vector<Camera> SplatTrainer::training_cameras() const {
  std::vector<Camera> cameras;
  for (std::size_t v = 0; v < dataset_.train.size(); ++v)
    cameras.push_back(config_.refine_poses ? pose_refiner_.camera(v, dataset_.train[v].camera)
                                           : dataset_.train[v].camera);
  return cameras;
}

PoseRefiner SplatTrainer::new_pose_refiner() const {
  std::vector<float> pivots;
  for (const DatasetView& view : dataset_.train) pivots.push_back(pose_pivot_depth(view.camera));
  return PoseRefiner(dataset_.train.size(), scene_extent_, pivots, config_.pose_adam_beta1);
}

float SplatTrainer::pose_pivot_depth(const Camera& camera) const {
  if (!config_.pose_pivot_at_scene) return 0.0f;
  const glm::vec3 centre = camera.camera_from_world_rotation * scene_centre_ + camera.camera_from_world_translation;
  return std::max(0.0f, centre.z);
}

Camera SplatTrainer::scoring_camera(const DatasetView& view) const {
  if (!config_.refine_poses) return view.camera;
  // Training moved the frame as a whole (a small turn, shift and scale): the view's recorded
  // pose is carried into the model's frame by the similarity the training views' poses
  // moved by, and the alignment then corrects what is the view's own.
  const Camera start_camera =
      fit_frame_change(recorded_training_cameras_, training_cameras()).applied_to(view.camera);
  PoseAlignmentSettings alignment;
  alignment.steps = config_.test_pose_alignment_steps;
  alignment.lr = {config_.pose_rotation_lr, config_.pose_translation_lr};
  // Decaying as training's rates do: large steps find the frame, small ones settle in it.
  alignment.lr_final_factor = config_.pose_lr_final_factor;
  alignment.ssim_weight = config_.ssim_weight;
  PoseCorrection start;
  start.pivot_depth = pose_pivot_depth(start_camera);
  return align_pose(model_, start_camera, view.image, render_settings(), alignment, scene_extent_, start)
      .correction.applied_to(start_camera);
}

Evaluation SplatTrainer::evaluate(const std::vector<DatasetView>& views, std::vector<Image>* renders) {
  // Under pose refinement the scene's frame has moved with the training poses: each view is
  // first aligned to its photograph with the model fixed, from its recorded pose every time
  // (so a score depends only on the model, and a resumed run scores as an uninterrupted one).
  return score_views(
      views, [&](const DatasetView& view) { return scoring_camera(view); },
      [&](const Camera& camera) { return render(camera); }, renders);
}

}  // namespace splat
