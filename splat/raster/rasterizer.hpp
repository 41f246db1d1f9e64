#pragma once
// The tile-based CPU rasterizer: project → bin and sort → blend. The frame's intermediate
// state lives in the RenderResult (its `frame`), which the backward pass takes explicitly;
// reusing one RenderResult (and one Rasterizer, for the backward's scratch) across frames or
// training iterations allocates nothing after the first.
#include "splat/core/camera.hpp"
#include "splat/gaussians/gaussian_model.hpp"
#include "splat/raster/bin_sort.hpp"
#include "splat/raster/blend.hpp"
#include "splat/raster/blend_backward.hpp"
#include "splat/raster/project_backward.hpp"
#include "splat/raster/project.hpp"
#include "splat/raster/render_result.hpp"

namespace splat {

struct RenderSettings {
  int sh_degree = kMaxShDegree;         // bands used; clamped to the model's degree
  float background[3] = {1, 1, 1};      // composited with the final transmittance
  // The gradient of α = min(0.99, o·G) where the clamp is active: zero (the exact derivative,
  // the default), or passed straight through as if unclamped, which is what the official CUDA
  // rasterizer's backward does (splat-grad uses it to compare with its gradients).
  AlphaClampGradient alpha_clamp_gradient = AlphaClampGradient::kZero;
  // Keep what Rasterizer::backward needs of the blend (where each tile-list entry blended,
  // each tile's overlap index, each pixel's final T and contributor count). Renders that are
  // only looked at (splat-render, the viewer, scoring) turn it off.
  bool for_backward = true;
};

// Wall time of each stage of a backward pass, in milliseconds.
struct BackwardTimings {
  double blend_backward_ms = 0, project_backward_ms = 0;
  double total_ms() const { return blend_backward_ms + project_backward_ms; }
};

// Gradients of a loss with respect to the model, from Rasterizer::backward.
struct RasterGradients {
  GaussianModel params;                     // ∂L/∂(raw parameters), shaped like the model
  std::vector<float> viewspace_grad_norm;   // [N] ‖∂L/∂(2D mean)‖ in NDC units (densification)
  std::vector<float> blend_weight;          // [N] Σ over pixels of Tα: how much of the image
                                            // each Gaussian makes (pruning by contribution)
  bool with_camera_pose = false;            // set to also get ∂L/∂(the camera's pose):
  CameraPoseGradient camera_pose;           // (pose refinement)
  // Set to get the SH coefficients' gradient as its two factors in `sh_factors`
  // (sh_gradient_factors.hpp: 6 floats a Gaussian for 48), which Adam takes as they are;
  // params.sh is then not written.
  bool sh_as_factors = false;
  ShGradientFactors sh_factors;
  BackwardTimings timings;                  // what the backward that wrote these took
};

class Rasterizer {
 public:
  // Renders `model` as seen by `camera` into `result` (resized to the camera's image), with
  // the stages' timings in result.timings. Throws ArgumentError for an inconsistent model or a camera without pixels.
  void render(const GaussianModel& model, const Camera& camera, const RenderSettings& settings,
              RenderResult& result);

  // Gradients of L with respect to every parameter of `model`, given v_color = ∂L/∂color
  // ([H, W, 3]) for the image in `forward`, which render() must have made of this same model,
  // camera and settings. Bit-identical for any thread count. grads.timings receives the
  // stages' timings.
  void backward(const GaussianModel& model, const Camera& camera, const RenderSettings& settings,
                const RenderResult& forward, const Image& v_color, RasterGradients& grads);

 private:
  OverlapGradients overlap_grads_;  // scratch for the backward pass
};

// Throws ArgumentError for an inconsistent model or a camera without pixels.
void check_render_inputs(const GaussianModel& model, const Camera& camera);

}  // namespace splat
