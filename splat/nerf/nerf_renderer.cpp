#include "splat/nerf/nerf_renderer.hpp"

#include <algorithm>

#include "splat/nerf/samplers.hpp"

namespace splat {

namespace {

// Rays per batch when rendering an image: the training batch size, so evaluation needs no
// more memory for the networks' activations than training does (the GEMMs already have tens
// of thousands of rows at this size).
constexpr std::size_t kImageBatchRays = 1024;

// Below this opacity of the coarse ray, the fine pass draws the background: what it could
// add there changes the pixel by about this much.
constexpr float kFineMinCoarseOpacity = 1e-3f;

// Fills the network inputs (sample points and the ray's direction) of a placed pass.
void fill_inputs(const SceneSpace& space, std::span<const Ray> rays, const std::vector<std::uint32_t>& offsets,
                 const std::vector<float>& t, std::vector<float>& positions, std::vector<float>& directions) {
  positions.resize(3 * t.size());
  directions.resize(3 * t.size());
  for (std::size_t r = 0; r < rays.size(); ++r)
    for (std::uint32_t i = offsets[r]; i < offsets[r + 1]; ++i) {
      const glm::vec3 p = space.to_network(rays[r].origin + t[i] * rays[r].direction);
      for (int a = 0; a < 3; ++a) {
        positions[3 * i + a] = p[a];
        directions[3 * i + a] = rays[r].direction[a];
      }
    }
}

}  // namespace

void NerfRenderer::place_coarse(const NerfModel& model, std::span<const Ray> rays, bool jitter,
                                std::mt19937& rng, Pass& pass) {
  const int n = model.settings.coarse_samples_for(/*evaluation=*/!jitter);
  pass.offsets.assign(rays.size() + 1, 0);
  pass.t.clear();
  pass.delta.clear();
  scratch_t_.resize(std::size_t(n));
  scratch_delta_.resize(std::size_t(n));
  const SceneSpace space = model.settings.space();
  for (std::size_t r = 0; r < rays.size(); ++r) {
    pass.offsets[r] = std::uint32_t(pass.t.size());
    if (!space.place_samples(rays[r], model.settings.near, jitter, rng, scratch_t_, scratch_delta_)) continue;
    const std::size_t kept = drop_empty_samples(model.grid, space, rays[r], scratch_t_, scratch_delta_);
    pass.t.insert(pass.t.end(), scratch_t_.begin(), scratch_t_.begin() + std::ptrdiff_t(kept));
    pass.delta.insert(pass.delta.end(), scratch_delta_.begin(),
                      scratch_delta_.begin() + std::ptrdiff_t(kept));
  }
  pass.offsets[rays.size()] = std::uint32_t(pass.t.size());
  fill_inputs(model.settings.space(), rays, pass.offsets, pass.t, pass.positions, pass.directions);
}

void NerfRenderer::place_fine(const NerfModel& model, std::span<const Ray> rays, bool jitter,
                              std::mt19937& rng, const Pass& coarse, Pass& pass) {
  const std::size_t n_fine = std::size_t(model.settings.fine_samples);
  pass.offsets.assign(rays.size() + 1, 0);
  pass.t.clear();
  pass.delta.clear();
  scratch_fine_.resize(n_fine);
  for (std::size_t r = 0; r < rays.size(); ++r) {
    pass.offsets[r] = std::uint32_t(pass.t.size());
    const std::uint32_t begin = coarse.offsets[r], end = coarse.offsets[r + 1];
    if (begin == end) continue;  // nothing in the box here: the background
    // Nor where the coarse pass saw (next to) nothing: about half of lego's rays, each of
    // which would cost the fine network as much as a ray through the object.
    if (coarse.render.alpha[r] < kFineMinCoarseOpacity) continue;
    // The fine pass refines only what the coarse one saw: up to and including the sample
    // where the coarse ray stopped (transmittance below the compositor's floor). The samples
    // behind a surface, most of a solid object's, carry no weight and would cost the fine
    // network as much as the visible ones.
    const std::size_t n = std::min<std::size_t>(end - begin, coarse.render.blended_count[r] + 1);
    const std::span<const float> ct(&coarse.t[begin], n), cd(&coarse.delta[begin], n),
        cw(&coarse.render.weights[begin], n);
    scratch_t_.resize(n + n_fine);
    scratch_delta_.resize(n + n_fine);
    hierarchical_samples(ct, cd, cw, jitter, rng, scratch_fine_, scratch_t_, scratch_delta_);
    pass.t.insert(pass.t.end(), scratch_t_.begin(), scratch_t_.end());
    pass.delta.insert(pass.delta.end(), scratch_delta_.begin(), scratch_delta_.end());
  }
  pass.offsets[rays.size()] = std::uint32_t(pass.t.size());
  fill_inputs(model.settings.space(), rays, pass.offsets, pass.t, pass.positions, pass.directions);
}

void NerfRenderer::evaluate(const NerfMlp& mlp, std::span<const Ray> rays, Pass& pass,
                            RayBackgrounds backgrounds) {
  const std::size_t s = pass.t.size();
  pass.sigma.resize(s);
  pass.rgb.resize(3 * s);
  if (s > 0) mlp.forward(pass.positions, pass.directions, pass.sigma, pass.rgb, pass.mlp);
  pass.render.resize(rays.size(), s);
  volume_render(pass.batch(), pass.sigma, pass.rgb, backgrounds, pass.render);
}

void NerfRenderer::forward(const NerfModel& model, std::span<const Ray> rays,
                           RayBackgrounds backgrounds, bool jitter, std::mt19937& rng,
                           NerfForwardContext& context) {
  context.backgrounds.assign(backgrounds.values, backgrounds.values + 3 * backgrounds.colors);
  place_coarse(model, rays, jitter, rng, context.coarse);
  evaluate(model.coarse, rays, context.coarse, context.ray_backgrounds());
  place_fine(model, rays, jitter, rng, context.coarse, context.fine);
  evaluate(model.fine, rays, context.fine, context.ray_backgrounds());
}

void NerfRenderer::backward_pass(const NerfMlp& mlp, Pass& pass, std::span<const float> v_color,
                                 RayBackgrounds backgrounds, std::span<float> v_params) {
  const std::size_t s = pass.t.size();
  if (s == 0) return;
  v_sigma_.resize(s);
  v_rgb_.resize(3 * s);
  volume_render_backward(pass.batch(), pass.sigma, pass.rgb, backgrounds, pass.render, v_color,
                         v_sigma_, v_rgb_);
  mlp.backward(pass.mlp, v_sigma_, v_rgb_, v_params);
}

void NerfRenderer::backward(const NerfModel& model, NerfForwardContext& context,
                            std::span<const float> v_coarse_color, std::span<const float> v_fine_color,
                            std::span<float> v_coarse_params, std::span<float> v_fine_params) {
  backward_pass(model.coarse, context.coarse, v_coarse_color, context.ray_backgrounds(), v_coarse_params);
  backward_pass(model.fine, context.fine, v_fine_color, context.ray_backgrounds(), v_fine_params);
}

Image NerfRenderer::render_image(const NerfModel& model, const Camera& camera, const float background[3],
                                 NerfForwardContext& context) {
  Image image;
  render_image_into(model, camera, background, image, [] { return false; }, context);
  return image;
}

Image NerfRenderer::render_image(const NerfModel& model, const Camera& camera,
                                 const float background[3]) {
  return render_image(model, camera, background, image_context_);
}

bool NerfRenderer::render_image(const NerfModel& model, const Camera& camera, const float background[3],
                                Image& image, const std::function<bool()>& cancelled) {
  return render_image_into(model, camera, background, image, cancelled, image_context_);
}

bool NerfRenderer::render_image_into(const NerfModel& model, const Camera& camera, const float background[3],
                                     Image& image, const std::function<bool()>& cancelled,
                                     NerfForwardContext& context) {
  camera_rays(camera, image_rays_);
  image = Image(camera.width, camera.height, 3);
  std::mt19937 unused_rng(0);
  for (std::size_t first = 0; first < image_rays_.size(); first += kImageBatchRays) {
    if (cancelled()) return false;
    const std::size_t count = std::min(kImageBatchRays, image_rays_.size() - first);
    forward(model, std::span<const Ray>(&image_rays_[first], count), background, false, unused_rng, context);
    std::copy(context.fine_color().begin(), context.fine_color().begin() + std::ptrdiff_t(3 * count),
              image.data.begin() + std::ptrdiff_t(3 * first));
  }
  return true;
}

}  // namespace splat
