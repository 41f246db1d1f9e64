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

class NerfRenderer {
 public:
  // Renders `rays`; `jitter` draws sample positions from `rng` (training), otherwise they are
  // deterministic midpoints (evaluation, settings.coarse_samples_for(true) of them; `rng`
  // unused). Keeps what backward needs.
  void forward(const NerfModel& model, std::span<const Ray> rays, const float background[3],
               bool jitter, std::mt19937& rng);

  // [R, 3] colours of the last forward, with the background.
  const std::vector<float>& coarse_color() const { return coarse_.render.color; }
  const std::vector<float>& fine_color() const { return fine_.render.color; }
  std::size_t coarse_sample_count() const { return coarse_.t.size(); }
  std::size_t fine_sample_count() const { return fine_.t.size(); }

  // Cotangents of the last forward's colours [R, 3] → v_coarse_params and v_fine_params
  // (the networks' parameter gradients), which this ADDS to.
  void backward(const NerfModel& model, std::span<const float> v_coarse_color,
                std::span<const float> v_fine_color, std::span<float> v_coarse_params,
                std::span<float> v_fine_params);

  // A whole image (fine colours), rendered in batches of rays without jitter.
  Image render_image(const NerfModel& model, const Camera& camera, const float background[3]);
  // The same into `image`, checking `cancelled` between batches: once it returns true the
  // render stops and this returns false, `image` incomplete (the viewer drops stale frames).
  bool render_image(const NerfModel& model, const Camera& camera, const float background[3], Image& image,
                    const std::function<bool()>& cancelled);

 private:
  // One pass (coarse or fine): samples, network inputs and outputs, compositing.
  struct Pass {
    std::vector<std::uint32_t> offsets;  // [R + 1]
    std::vector<float> t, delta;         // [S]
    std::vector<float> positions, directions, sigma, rgb;  // [S, 3] / [S]
    NerfMlpContext mlp;
    VolumeRenderResult render;
    std::vector<float> v_sigma, v_rgb;
    RaySampleBatch batch() const { return {offsets, t, delta}; }
  };
  void place_coarse(const NerfModel& model, std::span<const Ray> rays, bool jitter, std::mt19937& rng);
  void place_fine(const NerfModel& model, std::span<const Ray> rays, bool jitter, std::mt19937& rng);
  static void evaluate(const NerfMlp& mlp, std::span<const Ray> rays, Pass& pass,
                       const float background[3]);
  static void backward_pass(const NerfMlp& mlp, Pass& pass, std::span<const float> v_color,
                            const float background[3], std::span<float> v_params);

  Pass coarse_, fine_;
  std::vector<float> scratch_t_, scratch_delta_, scratch_fine_;
  float background_[3] = {1, 1, 1};
  std::vector<Ray> image_rays_;
};

}  // namespace splat
