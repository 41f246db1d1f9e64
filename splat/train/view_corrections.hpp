#pragma once
// The training views' own parameters, optimised per view beside the model: a correction of
// each view's camera pose (--refine-poses, pose_alignment.hpp) and an affine colour map per
// view (--exposure-compensation, exposure_compensation.hpp). Both keep one small block per
// view in a PerViewAdam, and a checkpoint stores them through that alone (states()).
#include <cstddef>
#include <type_traits>
#include <vector>

#include "splat/core/camera.hpp"
#include "splat/core/frame_change.hpp"
#include "splat/data/dataset.hpp"
#include "splat/gaussians/gaussian_model.hpp"
#include "splat/optim/per_view_adam.hpp"
#include "splat/raster/rasterizer.hpp"
#include "splat/train/exposure_compensation.hpp"
#include "splat/train/pose_alignment.hpp"
#include "splat/train/training_config.hpp"
#include "splat/train/view_step.hpp"

namespace splat {

class ViewCorrections {
 public:
  ViewCorrections() = default;
  // The corrections `config` turns on, for `dataset`'s training views, at the identity.
  ViewCorrections(const Dataset& dataset, const SplatTrainingConfig& config, float scene_extent);

  // The camera training view `view` is rendered with: `recorded` (its recorded camera, at any
  // image size), with the view's pose correction under pose refinement.
  Camera camera(std::size_t view, const Camera& recorded) const;
  // Every training view's camera as trained.
  std::vector<Camera> training_cameras() const;
  // The similarity the training views' poses have moved by as a whole under pose refinement
  // (the identity without it): what carries a pose recorded with theirs into the model's frame.
  FrameChange frame_change() const;
  // The camera a model is scored with for `view` (a test view): its recorded one, or under
  // pose refinement that camera aligned to the view's photograph with `model` fixed.
  Camera scoring_camera(const GaussianModel& model, const DatasetView& view, const RenderSettings& render) const;

  // Whether a step at `iteration` refines the poses (and so needs ∂L/∂pose).
  bool refines_poses_at(int iteration) const { return config_.refine_poses && iteration >= config_.pose_refine_from; }
  // One Adam step of view `view`'s pose correction from ∂L/∂pose of its render, at the rates
  // of `schedule_iteration`; then the frame is held (pose_hold_frame).
  void step_pose(std::size_t view, const Camera& recorded, const CameraPoseGradient& gradient,
                 double schedule_iteration);
  // View `view`'s exposure map for a step at `iteration` (none before exposure_from or
  // without compensation), stepped at the rate of `schedule_iteration`.
  ViewExposure exposure(std::size_t view, int iteration, double schedule_iteration);

  const PoseRefiner& pose_refiner() const { return pose_refiner_; }
  const ExposureCompensation& exposure_compensation() const { return exposure_; }

  // The per-view optimisers that are on, in the order a checkpoint stores them: each one's
  // state, and the checkpoint header's key for its views' step counts.
  template <class Adam>
  struct State {
    const char* steps_key;
    Adam* adam;
  };
  std::vector<State<PerViewAdam>> states();
  std::vector<State<const PerViewAdam>> states() const;

 private:
  template <class Self>
  static auto states_of(Self& self);
  PoseLearningRates pose_learning_rates(double schedule_iteration) const;
  // The pivot of `camera`'s pose correction: the depth of the scene's centre in front of it
  // under pose_pivot_at_scene (0 if behind it), else 0 (the camera centre).
  float pose_pivot_depth(const Camera& camera) const;

  SplatTrainingConfig config_;
  float scene_extent_ = 1.0f;
  std::vector<Camera> recorded_cameras_;  // [train view]
  glm::vec3 scene_centre_{0.0f};          // the point cloud's median, else the cameras' mean
  PoseRefiner pose_refiner_;              // [train view] under refine_poses
  ExposureCompensation exposure_;         // [train view] under exposure_compensation
};

}  // namespace splat
