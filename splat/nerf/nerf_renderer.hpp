#pragma once
// Renders batches of rays through a NerfModel, coarse then fine, and back-propagates a
// colour cotangent into both networks' parameters.
//
// Per ray: stratified coarse samples between the box entry and exit, those in empty
// occupancy cells dropped; the coarse network and the shared compositor give the coarse
// colour and weights; importance samples drawn from those weights, merged with the coarse
// positions, go through the fine network for the fine colour; the fine pass stops where the
// coarse ray became opaque. A ray that misses the box, whose samples all fall in empty cells,
// or whose coarse opacity is below 10⁻³, shows the background in the fine pass.
//
// Sample placement is serial in ray order (from the caller's RNG when jittered), the
// networks and the compositing are parallel and deterministic: the same seed gives the same
// image and gradients for any thread count. Buffers are reused across batches.
#include <functional>
#include <random>
#include <span>
#include <vector>

#include "splat/core/camera.hpp"
#include "splat/core/image.hpp"
#include "splat/nerf/nerf_model.hpp"
#include "splat/nerf/volume_render.hpp"

namespace splat {

// What one forward pass over a batch of rays made, and what its backward needs: each pass's
// samples, network activations and compositing, and the background. The caller owns it, as
// it owns the rasterizer's RenderResult, so a backward names the forward it differentiates;
// one context reused across batches allocates nothing once it has grown.
struct NerfForwardContext {
  // One pass (coarse or fine): samples, network inputs and outputs, compositing.
  struct Pass {
    std::vector<std::uint32_t> offsets;  // [R + 1]
    std::vector<float> t, delta;         // [S]
    std::vector<float> positions, directions, sigma, rgb;  // [S, 3] / [S]
    NerfMlpContext mlp;                  // the network's activations (its backward's scratch too)
    VolumeRenderResult render;
    RaySampleBatch batch() const { return {offsets, t, delta}; }
  };
  Pass coarse, fine;
  // The colour behind the rays, as forward() was given it: 3 values for all, or [R, 3].
  std::vector<float> backgrounds = {1, 1, 1};
  RayBackgrounds ray_backgrounds() const {
    return backgrounds.size() == 3 ? RayBackgrounds(backgrounds.data()) : RayBackgrounds(std::span(backgrounds));
  }

  // [R, 3] colours, with the background.
  const std::vector<float>& coarse_color() const { return coarse.render.color; }
  const std::vector<float>& fine_color() const { return fine.render.color; }
  std::size_t coarse_sample_count() const { return coarse.t.size(); }
  std::size_t fine_sample_count() const { return fine.t.size(); }
};

class NerfRenderer {
 public:
  // Renders `rays` into `context`; `jitter` draws sample positions from `rng` (training),
  // otherwise they are deterministic midpoints (evaluation, settings.coarse_samples_for(true)
  // of them; `rng` unused). `backgrounds`: one colour, or one per ray.
  void forward(const NerfModel& model, std::span<const Ray> rays, RayBackgrounds backgrounds,
               bool jitter, std::mt19937& rng, NerfForwardContext& context);

  // Cotangents of `context`'s colours [R, 3] (from forward() with this model) →
  // v_coarse_params and v_fine_params (the networks' parameter gradients), which this ADDS
  // to. The networks' backward uses the context's activations as scratch.
  void backward(const NerfModel& model, NerfForwardContext& context, std::span<const float> v_coarse_color,
                std::span<const float> v_fine_color, std::span<float> v_coarse_params,
                std::span<float> v_fine_params);

  // A whole image (fine colours), rendered in batches of rays without jitter through
  // `context` (which it overwrites: a trainer passes its training context rather than hold a
  // second one), or through the renderer's own.
  Image render_image(const NerfModel& model, const Camera& camera, const float background[3],
                     NerfForwardContext& context);
  Image render_image(const NerfModel& model, const Camera& camera, const float background[3]);
  // The same into `image`, checking `cancelled` between batches: once it returns true the
  // render stops and this returns false, `image` incomplete (the viewer drops stale frames).
  bool render_image(const NerfModel& model, const Camera& camera, const float background[3], Image& image,
                    const std::function<bool()>& cancelled);

 private:
  using Pass = NerfForwardContext::Pass;
  bool render_image_into(const NerfModel& model, const Camera& camera, const float background[3], Image& image,
                         const std::function<bool()>& cancelled, NerfForwardContext& context);
  void place_coarse(const NerfModel& model, std::span<const Ray> rays, bool jitter, std::mt19937& rng,
                    Pass& pass);
  void place_fine(const NerfModel& model, std::span<const Ray> rays, bool jitter, std::mt19937& rng,
                  const Pass& coarse, Pass& pass);
  static void evaluate(const NerfMlp& mlp, std::span<const Ray> rays, Pass& pass,
                       RayBackgrounds backgrounds);
  void backward_pass(const NerfMlp& mlp, Pass& pass, std::span<const float> v_color,
                     RayBackgrounds backgrounds, std::span<float> v_params);

  // Scratch: one ray's samples while placing them, and a pass's cotangents in the backward.
  std::vector<float> scratch_t_, scratch_delta_, scratch_fine_, v_sigma_, v_rgb_;
  std::vector<Ray> image_rays_;
  NerfForwardContext image_context_;  // render_image's own, grown only if used
};

}  // namespace splat
