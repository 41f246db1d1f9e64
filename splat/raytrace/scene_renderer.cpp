#include "splat/raytrace/scene_renderer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

namespace splat::raytrace {
namespace {

constexpr int kTileSize = 16;

// SplitMix64: a tiny generator with a good avalanche, enough for pixel jitter and fully
// specified (std:: distributions differ between standard libraries).
struct PixelRandom {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  float uniform() { return float(next() >> 40) * (1.0f / 16777216.0f); }  // [0, 1), 24 bits
};

PixelRandom pixel_random(unsigned seed, unsigned view, std::uint64_t pixel) {
  PixelRandom r{(std::uint64_t(seed) << 32) ^ (std::uint64_t(view) * 0x100000001B3ull)};
  r.state ^= r.next() + pixel;  // mix the pixel in after scrambling (seed, view)
  r.next();
  return r;
}

}  // namespace

float linear_to_srgb(float linear) {
  const float c = std::clamp(linear, 0.0f, 1.0f);
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

RenderedView render_view(const Mesh& mesh, const RayTracer& tracer, const Lighting& lighting,
                         const Camera& camera, const RenderSettings& settings, unsigned view) {
  const int width = camera.width, height = camera.height;
  RenderedView out{Image(width, height, 4), Image(width, height, 1)};
  const glm::mat3 world_from_camera = glm::transpose(camera.camera_from_world_rotation);
  const glm::vec3 origin = camera.center_in_world();
  const int spp = settings.samples_per_pixel;

  // A ray through image position (px, py) in pixels; its direction in camera axes has z = 1
  // before normalising, so camera depth = t / |d_cam|.
  auto world_direction = [&](float px, float py) {
    return glm::normalize(
        world_from_camera * glm::vec3((px - camera.cx) / camera.fx, (py - camera.cy) / camera.fy, 1.0f));
  };

  tbb::parallel_for(
      tbb::blocked_range2d<int>(0, height, kTileSize, 0, width, kTileSize),
      [&](const tbb::blocked_range2d<int>& tile) {
        for (int y = tile.rows().begin(); y < tile.rows().end(); ++y)
          for (int x = tile.cols().begin(); x < tile.cols().end(); ++x) {
            const std::uint64_t pixel = std::uint64_t(y) * width + x;
            RayHit hit;
            const glm::vec3 centre_dir = world_direction(float(x) + 0.5f, float(y) + 0.5f);
            if (tracer.intersect(origin, centre_dir, hit))
              out.depth.data[pixel] = camera.camera_from_world(origin + hit.t * centre_dir).z;

            PixelRandom random = pixel_random(settings.seed, view, pixel);
            glm::vec3 sum(0.0f);
            int hits = 0;
            for (int s = 0; s < spp; ++s) {
              // One sample is the pixel centre when spp = 1, so a 1-sample render is aliased
              // but unbiased towards the depth ray; more samples jitter uniformly.
              const float jx = spp == 1 ? 0.5f : random.uniform();
              const float jy = spp == 1 ? 0.5f : random.uniform();
              const glm::vec3 dir = world_direction(float(x) + jx, float(y) + jy);
              if (!tracer.intersect(origin, dir, hit)) continue;
              // Clamped per sample, as a display would: one over-bright highlight sample
              // must not brighten a whole anti-aliased edge.
              sum += glm::clamp(shade(mesh, tracer, lighting, hit, origin, dir), 0.0f, 1.0f);
              ++hits;
            }
            float* rgba = &out.color.data[pixel * 4];
            const float coverage = float(hits) / float(spp);
            // Straight (not premultiplied) colour: the mean over the samples that hit, so an
            // edge pixel keeps the surface's colour and only its alpha falls off.
            const glm::vec3 mean = hits > 0 ? sum / float(hits) : glm::vec3(0.0f);
            for (int c = 0; c < 3; ++c) {
              const float encoded = linear_to_srgb(mean[c]);
              // With a background, composite in the encoded values exactly as datasets do
              // with RGBA images (splat::composite_onto), so both routes give the same pixels.
              rgba[c] = settings.background
                            ? encoded * coverage + (*settings.background)[c] * (1.0f - coverage)
                            : encoded;
            }
            rgba[3] = settings.background ? 1.0f : coverage;
          }
      },
      tbb::simple_partitioner());
  return out;
}

}  // namespace splat::raytrace
