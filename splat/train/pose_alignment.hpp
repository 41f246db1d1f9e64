#pragma once
// Views' poses corrected by gradient descent: refinement of the training views during
// training (--refine-poses), and alignment of a view with the model held fixed, the protocol
// for scoring a model trained with refinement (each test view is first aligned to its
// photograph, since training moved the frame the poses live in). A correction is a
// quaternion and a translation in the camera's frame (apply_pose_correction in
// splat/raster/projection_math.hpp); its gradient is the rasterizer's ∂L/∂pose chained
// through apply_pose_correction_vjp.
#include <cstddef>
#include <vector>

#include "splat/core/camera.hpp"
#include "splat/core/image.hpp"
#include "splat/gaussians/gaussian_model.hpp"
#include "splat/optim/per_view_adam.hpp"
#include "splat/raster/rasterizer.hpp"

namespace splat {

// Rotation (w, x, y, z; normalised on use) and translation applied to a pose, the rotation
// about a pivot on the camera's optical axis (apply_pose_correction).
struct PoseCorrection {
  glm::vec4 rotation{1.0f, 0.0f, 0.0f, 0.0f};
  glm::vec3 translation{0.0f};
  float pivot_depth = 0.0f;  // fixed, not optimised; 0: about the camera centre

  Camera applied_to(const Camera& camera) const;
};

// The correction about `pivot_depth` that takes `from`'s pose to `to`'s.
PoseCorrection correction_between(const Camera& from, const Camera& to, float pivot_depth);

struct PoseLearningRates {
  float rotation = 1e-3f;     // Adam's step on the quaternion's components
  float translation = 1e-3f;  // Adam's step on τ, in units of the scene extent
};

// The corrections of `views` views, each with its own Adam state: a view's correction moves
// only on the iterations that train on it.
class PoseRefiner {
 public:
  PoseRefiner() = default;
  // `scene_extent` scales the translation's step, so that one learning rate suits scenes of
  // any size. `pivot_depths` (one per view, or none: 0) are the corrections' pivots.
  // `adam_beta1`: Adam's first-moment decay (PyTorch's 0.9 unless given).
  PoseRefiner(std::size_t views, float scene_extent, std::vector<float> pivot_depths = {}, double adam_beta1 = 0.9);

  std::size_t views() const { return adam_.views(); }
  PoseCorrection correction(std::size_t view) const;
  // `base` (view `view`'s recorded camera, at any image size) with the correction applied.
  Camera camera(std::size_t view, const Camera& base) const { return correction(view).applied_to(base); }
  // Starts view `view` from `correction`'s rotation and translation (its pivot and Adam state
  // unchanged).
  void set_correction(std::size_t view, const PoseCorrection& correction);

  // Takes out of the corrections the similarity they share (fit_frame_change between
  // `recorded`, every view's recorded camera, and the corrected ones), leaving each view's
  // own. A scene and its poses are only defined up to a similarity; left free, the frame
  // drifts with the noise of the poses' gradients, and the model has to follow it.
  void hold_frame(const std::vector<Camera>& recorded);

  // One Adam step of view `view`'s correction, from ∂L/∂pose of a render with camera(view, base).
  void step(std::size_t view, const Camera& base, const CameraPoseGradient& gradient,
            const PoseLearningRates& lr);

  // The corrections and their optimiser, as checkpoints store and restore them: 7 numbers
  // per view (the quaternion, then τ).
  const PerViewAdam& state() const { return adam_; }
  PerViewAdam& state() { return adam_; }

 private:
  float extent_ = 1.0f;
  std::vector<float> pivot_depths_;  // [view]
  PerViewAdam adam_;  // per view: the quaternion (w, x, y, z), then τ
};

struct PoseAlignmentSettings {
  int steps = 100;
  PoseLearningRates lr;           // at the first step, decaying exponentially to
  float lr_final_factor = 1.0f;   // this factor of it at the last (1: constant; a 2° error
                                  // in 200 steps is recovered to 0.014° constant, 0.07°
                                  // decaying to 0.1, 0.27° decaying to 0.01)
  float ssim_weight = 0.2f;      // the training loss's λ
};

struct PoseAlignmentResult {
  PoseCorrection correction;  // the one with the lowest loss seen (`start` included)
  double first_loss = 0;      // at `start`
  double loss = 0;            // at `correction`
};

// Adam on the correction of `camera`'s pose that makes `model`'s render match `photo` (the
// training loss), `settings.steps` steps, starting from `start`; returns the best correction
// seen. Deterministic for any thread count.
PoseAlignmentResult align_pose(const GaussianModel& model, const Camera& camera, const Image& photo,
                               const RenderSettings& render, const PoseAlignmentSettings& settings,
                               float scene_extent, const PoseCorrection& start = {});

}  // namespace splat
