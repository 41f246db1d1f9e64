#pragma once
// One view's part of a training step: render the model from the view's camera, score the
// render against the photograph ((1 − λ)·L1 + λ·(1 − SSIM), through the view's exposure map
// when one is given), and back-propagate the loss to the parameters (and to the camera's
// pose under pose refinement). What is kept between views (the rasterizer's scratch, the
// render, the gradients, SSIM's buffers) is reused, so after the first view a step allocates
// nothing; the results stay readable until the next run().
#include <cstddef>

#include "splat/core/camera.hpp"
#include "splat/core/image.hpp"
#include "splat/gaussians/gaussian_model.hpp"
#include "splat/optim/masked_loss.hpp"
#include "splat/optim/photometric_loss.hpp"
#include "splat/raster/rasterizer.hpp"
#include "splat/train/exposure_compensation.hpp"
#include "splat/train/step_result.hpp"

namespace splat {

struct ViewStepSettings {
  RenderSettings render;
  float ssim_weight = kDefaultSsimWeight;  // λ
  bool camera_pose_gradient = false;       // also ∂L/∂(the camera's pose)
  bool sh_gradient_factors = false;        // the SH gradient as its factors (RasterGradients::sh_as_factors)
  // Skip the backward pass when the loss is not finite (the caller then stops the run). A
  // rank of a data-parallel step differentiates anyway: the ranks must all take part in the
  // exchange, which finds the batch's loss non-finite for all of them at once.
  bool stop_on_non_finite_loss = true;
};

// The view's exposure map (exposure_compensation.hpp): the render passes through it before
// the loss, and the loss's gradient takes one Adam step of it.
struct ViewExposure {
  ExposureCompensation* maps = nullptr;  // null: the render is scored as it is
  std::size_t view = 0;
  float lr = 0;
};

struct ViewStepResult {
  LossValue loss;
  bool differentiated = false;  // false: the loss was not finite, nothing was back-propagated
  // forward, loss and backward, and the rasterizer's stages inside them (the rest are 0).
  IterationTimings timings;
};

class ViewStep {
 public:
  // Renders `model` from `camera`, scores the render against `target` (the photograph at
  // the camera's image size) over the pixels `mask` keeps (masked_loss.hpp; null: all) and
  // back-propagates the loss into gradients().
  ViewStepResult run(const GaussianModel& model, const Camera& camera, const Image& target,
                     const ViewStepSettings& settings, const ViewExposure& exposure = {},
                     const Image* mask = nullptr);

  // The last run's render and gradients (its statistics for the density strategy included).
  const RenderResult& render() const { return render_; }
  const RasterGradients& gradients() const { return grads_; }
  // The same, for a caller that takes the gradient over (PairwiseSum::take swaps it out: the
  // next run overwrites it whole).
  RasterGradients& gradients() { return grads_; }

 private:
  Rasterizer rasterizer_;
  RenderResult render_;
  RasterGradients grads_;
  Image v_image_;       // ∂L/∂(the render)
  Image compensated_;   // the render through the view's exposure map
  SsimScratch ssim_scratch_;
  MaskedLossScratch masked_scratch_;
};

}  // namespace splat
