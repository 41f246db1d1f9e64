#include "splat/nerf/volume_render.hpp"

#include <string>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "splat/core/error.hpp"
#include "splat/nerf/ray_composite.hpp"

namespace splat {

namespace {

void expect_size(std::size_t actual, std::size_t expected, const char* what) {
  if (actual != expected)
    throw ArgumentError(std::string("volume render: ") + what + " has " + std::to_string(actual) +
                        " values, expected " + std::to_string(expected));
}

// The offsets must partition [0, S) into consecutive ray ranges.
void check_batch(const RaySampleBatch& samples, std::span<const float> sigma,
                 std::span<const float> rgb) {
  if (samples.ray_offsets.empty())
    throw ArgumentError("volume render: ray_offsets needs R + 1 entries, got none");
  const std::size_t s = samples.sample_count(), r = samples.ray_count();
  if (samples.ray_offsets[0] != 0 || samples.ray_offsets[r] != s)
    throw ArgumentError("volume render: ray_offsets must run from 0 to the sample count " +
                        std::to_string(s));
  for (std::size_t i = 0; i < r; ++i)
    if (samples.ray_offsets[i] > samples.ray_offsets[i + 1])
      throw ArgumentError("volume render: ray_offsets decrease at ray " + std::to_string(i));
  expect_size(samples.delta.size(), s, "delta");
  expect_size(sigma.size(), s, "sigma");
  expect_size(rgb.size(), 3 * s, "rgb");
}

void check_backgrounds(const RayBackgrounds& backgrounds, std::size_t rays) {
  if (backgrounds.values == nullptr && rays > 0)
    throw ArgumentError("volume render: no background colour");
  if (backgrounds.stride != 0 && backgrounds.colors != rays)
    throw ArgumentError("volume render: " + std::to_string(backgrounds.colors) +
                        " background colours for " + std::to_string(rays) + " rays");
}

// Rays per task: enough work to amortise scheduling; the split does not affect results.
constexpr std::size_t kRayGrain = 64;

}  // namespace

void VolumeRenderResult::resize(std::size_t rays, std::size_t samples) {
  color.resize(3 * rays);
  alpha.resize(rays);
  depth.resize(rays);
  final_transmittance.resize(rays);
  blended_count.resize(rays);
  sample_alpha.resize(samples);
  weights.resize(samples);
}

void volume_render(const RaySampleBatch& samples, std::span<const float> sigma,
                   std::span<const float> rgb, RayBackgrounds backgrounds,
                   VolumeRenderResult& result) {
  check_batch(samples, sigma, rgb);
  check_backgrounds(backgrounds, samples.ray_count());
  result.resize(samples.ray_count(), samples.sample_count());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, samples.ray_count(), kRayGrain),
                    [&](const tbb::blocked_range<std::size_t>& rays) {
    for (std::size_t r = rays.begin(); r < rays.end(); ++r) {
      const std::size_t begin = samples.ray_offsets[r], end = samples.ray_offsets[r + 1];
      // Pointers are data() + offset, not &span[offset]: an empty last ray starts at S.
      for (std::size_t i = begin; i < end; ++i)
        result.sample_alpha[i] = density_to_alpha(sigma[i], samples.delta[i]);
      const RayComposite<float> ray =
          composite_ray(end - begin, result.sample_alpha.data() + begin, rgb.data() + 3 * begin,
                        samples.t.data() + begin, backgrounds.of(r), result.weights.data() + begin);
      for (int c = 0; c < 3; ++c) result.color[3 * r + c] = ray.color[c];
      result.alpha[r] = ray.alpha;
      result.depth[r] = ray.depth;
      result.final_transmittance[r] = ray.final_transmittance;
      result.blended_count[r] = ray.blended_count;
    }
  });
}

void volume_render_backward(const RaySampleBatch& samples, std::span<const float> sigma,
                            std::span<const float> rgb, RayBackgrounds backgrounds,
                            const VolumeRenderResult& forward, std::span<const float> v_color,
                            std::span<float> v_sigma, std::span<float> v_rgb) {
  check_batch(samples, sigma, rgb);
  check_backgrounds(backgrounds, samples.ray_count());
  const std::size_t r_count = samples.ray_count(), s_count = samples.sample_count();
  expect_size(forward.final_transmittance.size(), r_count, "the forward result (rays)");
  expect_size(forward.blended_count.size(), r_count, "the forward result (rays)");
  expect_size(forward.sample_alpha.size(), s_count, "the forward result (samples)");
  expect_size(v_color.size(), 3 * r_count, "v_color");
  expect_size(v_sigma.size(), s_count, "v_sigma");
  expect_size(v_rgb.size(), 3 * s_count, "v_rgb");
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, r_count, kRayGrain),
                    [&](const tbb::blocked_range<std::size_t>& rays) {
    for (std::size_t r = rays.begin(); r < rays.end(); ++r) {
      const std::size_t begin = samples.ray_offsets[r], end = samples.ray_offsets[r + 1];
      RayComposite<float> ray{};
      ray.final_transmittance = forward.final_transmittance[r];
      ray.blended_count = forward.blended_count[r];
      // ∂L/∂α goes into v_sigma first, then becomes ∂L/∂σ in place (no scratch).
      composite_ray_vjp(end - begin, forward.sample_alpha.data() + begin,
                        rgb.data() + 3 * begin, ray, backgrounds.of(r), v_color.data() + 3 * r,
                        v_sigma.data() + begin, v_rgb.data() + 3 * begin);
      for (std::size_t i = begin; i < end; ++i)
        v_sigma[i] = density_to_alpha_vjp(sigma[i], samples.delta[i], v_sigma[i]);
    }
  });
}

}  // namespace splat
