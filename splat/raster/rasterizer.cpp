#include "splat/raster/rasterizer.hpp"

#include <chrono>
#include <string>

#include "splat/core/error.hpp"
#include "splat/raster/project_backward.hpp"

namespace splat {

namespace {
using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}
}  // namespace

void check_render_inputs(const GaussianModel& model, const Camera& camera) {
  model.check_consistent();
  if (camera.width <= 0 || camera.height <= 0)
    throw ArgumentError("render: camera image size " + std::to_string(camera.width) + "x" +
                        std::to_string(camera.height) + " has no pixels");
}

void Rasterizer::render(const GaussianModel& model, const Camera& camera,
                        const RenderSettings& settings, RenderResult& result) {
  check_render_inputs(model, camera);
  RasterFrame& frame = result.frame;
  frame.grid = TileGrid::for_image(camera.width, camera.height);
  result.resize(camera.width, camera.height, settings.for_backward);

  auto start = Clock::now();
  project_gaussians(model, camera, settings.sh_degree, frame.projected);
  result.timings.project_ms = ms_since(start);

  start = Clock::now();
  bin_and_sort(frame.projected, frame.grid, settings.for_backward, frame.bins);
  result.timings.bin_sort_ms = ms_since(start);

  start = Clock::now();
  blend_tiles(frame.projected, frame.bins, frame.grid, settings.background, settings.for_backward, result);
  result.timings.blend_ms = ms_since(start);
}

void Rasterizer::backward(const GaussianModel& model, const Camera& camera,
                          const RenderSettings& settings, const RenderResult& forward,
                          const Image& v_color, RasterGradients& grads) {
  if (v_color.width != camera.width || v_color.height != camera.height || v_color.channels != 3 ||
      forward.color.width != camera.width || forward.color.height != camera.height)
    throw ArgumentError("backward: the colour cotangent and the forward result must match the "
                        "camera's " + std::to_string(camera.width) + "x" +
                        std::to_string(camera.height) + " image with 3 channels");
  const RasterFrame& frame = forward.frame;
  if (frame.projected.splats.size() != model.size())
    throw ArgumentError("backward: the forward result was rendered from a different model");

  auto start = Clock::now();
  blend_tiles_backward(frame.projected, frame.bins, frame.grid, settings.background,
                       settings.alpha_clamp_gradient, forward, v_color, overlap_grads_);
  grads.timings.blend_backward_ms = ms_since(start);

  start = Clock::now();
  project_gaussians_backward(model, camera, settings.sh_degree, frame.bins,
                             overlap_grads_, grads.params, grads.viewspace_grad_norm,
                             grads.blend_weight, grads.with_camera_pose ? &grads.camera_pose : nullptr,
                             grads.sh_as_factors ? &grads.sh_factors : nullptr);
  grads.timings.project_backward_ms = ms_since(start);
}

}  // namespace splat
