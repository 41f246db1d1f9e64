#pragma once
// A view's pose corrected by gradient descent with the model held fixed: the protocol for
// scoring a model trained with pose refinement (each test view is first aligned to its
// photograph, since training moved the frame the poses live in), and the building block of
// refinement itself. The correction is a quaternion and a translation in the camera's frame
// (apply_pose_correction in splat/raster/projection_math.hpp), its gradient the rasterizer's
// ∂L/∂pose chained through apply_pose_correction_vjp.
#include "splat/core/camera.hpp"
#include "splat/core/image.hpp"
#include "splat/gaussians/gaussian_model.hpp"
#include "splat/raster/rasterizer.hpp"

namespace splat {

// Rotation (w, x, y, z; normalised on use) and translation applied to a pose.
struct PoseCorrection {
  glm::vec4 rotation{1.0f, 0.0f, 0.0f, 0.0f};
  glm::vec3 translation{0.0f};

  Camera applied_to(const Camera& camera) const;
};

struct PoseAlignmentSettings {
  int steps = 100;
  float rotation_lr = 1e-3f;       // Adam step on the quaternion's components
  float translation_lr = 1e-3f;    // Adam step on τ, in units of the scene extent
  float ssim_weight = 0.2f;        // the training loss's λ
};

struct PoseAlignmentResult {
  PoseCorrection correction;
  double first_loss = 0, last_loss = 0;  // before the first and after the last step
};

// Adam on the correction of `camera`'s pose that makes `model`'s render match `photo`
// (the training loss), `settings.steps` steps, starting from `start`. `scene_extent` scales
// the translation's step. Deterministic for any thread count.
PoseAlignmentResult align_pose(const GaussianModel& model, const Camera& camera, const Image& photo,
                               const RenderSettings& render, const PoseAlignmentSettings& settings,
                               float scene_extent, const PoseCorrection& start = {});

}  // namespace splat
