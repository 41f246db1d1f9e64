#include "splat/train/view_corrections.hpp"

#include <algorithm>

#include "splat/optim/lr_schedule.hpp"

namespace splat {

ViewCorrections::ViewCorrections(const Dataset& dataset, const SplatTrainingConfig& config, float scene_extent)
    : config_(config), scene_extent_(scene_extent), recorded_cameras_(cameras_of(dataset.train)) {
  if (config_.refine_poses) {
    scene_centre_ = scene_centre(dataset.train, dataset.points ? &*dataset.points : nullptr);
    std::vector<float> pivots;
    for (const Camera& camera : recorded_cameras_) pivots.push_back(pose_pivot_depth(camera));
    pose_refiner_ = PoseRefiner(recorded_cameras_.size(), scene_extent_, pivots, config_.pose_adam_beta1);
  }
  if (config_.exposure_compensation) exposure_ = ExposureCompensation(recorded_cameras_.size());
}

Camera ViewCorrections::camera(std::size_t view, const Camera& recorded) const {
  return config_.refine_poses ? pose_refiner_.camera(view, recorded) : recorded;
}

std::vector<Camera> ViewCorrections::training_cameras() const {
  std::vector<Camera> cameras;
  for (std::size_t v = 0; v < recorded_cameras_.size(); ++v) cameras.push_back(camera(v, recorded_cameras_[v]));
  return cameras;
}

FrameChange ViewCorrections::frame_change() const {
  return config_.refine_poses ? fit_frame_change(recorded_cameras_, training_cameras()) : FrameChange{};
}

float ViewCorrections::pose_pivot_depth(const Camera& camera) const {
  if (!config_.pose_pivot_at_scene) return 0.0f;
  const glm::vec3 centre = camera.camera_from_world_rotation * scene_centre_ + camera.camera_from_world_translation;
  return std::max(0.0f, centre.z);
}

PoseLearningRates ViewCorrections::pose_learning_rates(double schedule_iteration) const {
  const double fraction = schedule_iteration / double(config_.position_lr_max_steps) / config_.pose_lr_decay_until;
  const auto decayed = [&](float lr) {
    if (lr == 0.0f) return 0.0f;
    return float(ExponentialLrSchedule{lr, lr * config_.pose_lr_final_factor, 1}.at_fraction(std::min(1.0, fraction)));
  };
  return {decayed(config_.pose_rotation_lr), decayed(config_.pose_translation_lr)};
}

void ViewCorrections::step_pose(std::size_t view, const Camera& recorded, const CameraPoseGradient& gradient,
                                double schedule_iteration) {
  pose_refiner_.step(view, recorded, gradient, pose_learning_rates(schedule_iteration));
  if (config_.pose_hold_frame) pose_refiner_.hold_frame(recorded_cameras_);
}

ViewExposure ViewCorrections::exposure(std::size_t view, int iteration, double schedule_iteration) {
  if (!config_.exposure_compensation || iteration < config_.exposure_from) return {};
  return {&exposure_, view, config_.exposure_lr * appearance_lr_factor(config_, schedule_iteration)};
}

Camera ViewCorrections::scoring_camera(const GaussianModel& model, const DatasetView& view,
                                       const RenderSettings& render) const {
  if (!config_.refine_poses) return view.camera;
  // Training moved the frame as a whole (a small turn, shift and scale): the view's recorded
  // pose is carried into the model's frame by the similarity the training views' poses
  // moved by, and the alignment then corrects what is the view's own.
  const Camera start_camera = frame_change().applied_to(view.camera);
  PoseAlignmentSettings alignment;
  alignment.steps = config_.test_pose_alignment_steps;
  alignment.lr = {config_.pose_rotation_lr, config_.pose_translation_lr};
  // Decaying as training's rates do: large steps find the frame, small ones settle in it.
  alignment.lr_final_factor = config_.pose_lr_final_factor;
  alignment.ssim_weight = config_.ssim_weight;
  PoseCorrection start;
  start.pivot_depth = pose_pivot_depth(start_camera);
  return align_pose(model, start_camera, view.image, render, alignment, scene_extent_, start)
      .correction.applied_to(start_camera);
}

template <class Self>
auto ViewCorrections::states_of(Self& self) {
  std::vector<State<std::remove_reference_t<decltype(self.exposure_.state())>>> states;
  if (self.config_.refine_poses) states.push_back({"pose_steps", &self.pose_refiner_.state()});
  if (self.config_.exposure_compensation) states.push_back({"exposure_steps", &self.exposure_.state()});
  return states;
}

std::vector<ViewCorrections::State<PerViewAdam>> ViewCorrections::states() { return states_of(*this); }
std::vector<ViewCorrections::State<const PerViewAdam>> ViewCorrections::states() const { return states_of(*this); }

}  // namespace splat
