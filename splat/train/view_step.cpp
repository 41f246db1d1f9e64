#include "splat/train/view_step.hpp"

#include <cmath>

#include "splat/train/training_support.hpp"

namespace splat {

using training::Clock;
using training::ms_since;

ViewStepResult ViewStep::run(const GaussianModel& model, const Camera& camera, const Image& target,
                             const ViewStepSettings& settings, const ViewExposure& exposure, const Image* mask) {
  ViewStepResult result;
  auto start = Clock::now();
  rasterizer_.render(model, camera, settings.render, render_);
  result.timings.forward = ms_since(start);
  result.timings.project = render_.timings.project_ms;
  result.timings.bin_sort = render_.timings.bin_sort_ms;
  result.timings.blend = render_.timings.blend_ms;

  start = Clock::now();
  if (exposure.maps) exposure.maps->apply(exposure.view, render_.color, compensated_);
  const Image& scored = exposure.maps ? compensated_ : render_.color;
  result.loss = mask ? masked_photometric_loss(scored, target, *mask, settings.ssim_weight, &v_image_, masked_scratch_)
                     : photometric_loss(scored, target, settings.ssim_weight, &v_image_, ssim_scratch_);
  if (exposure.maps) exposure.maps->backward_and_step(exposure.view, render_.color, v_image_, exposure.lr);
  result.timings.loss = ms_since(start);
  if (settings.stop_on_non_finite_loss && !std::isfinite(result.loss.loss)) return result;

  start = Clock::now();
  grads_.with_camera_pose = settings.camera_pose_gradient;
  grads_.sh_as_factors = settings.sh_gradient_factors;
  rasterizer_.backward(model, camera, settings.render, render_, v_image_, grads_);
  result.differentiated = true;
  result.timings.backward = ms_since(start);
  result.timings.blend_backward = grads_.timings.blend_backward_ms;
  result.timings.project_backward = grads_.timings.project_backward_ms;
  return result;
}

}  // namespace splat
