#pragma once
// Renders one view of a loaded scene: several jittered rays per pixel, coverage as alpha,
// and the depth of the pixel centre's first hit. Deterministic for any thread count: every
// pixel draws its jitter from its own generator seeded by (seed, view, pixel).
#include <optional>

#include "splat/raytrace/gltf_mesh.hpp"
#include "splat/raytrace/ray_tracer.hpp"
#include "splat/raytrace/shading.hpp"
#include "splat/core/camera.hpp"
#include "splat/core/image.hpp"

namespace splat::raytrace {

struct RenderSettings {
  int samples_per_pixel = 16;
  unsigned seed = 0;
  // None: straight colour of the covered part with alpha = coverage. Given: the image is
  // composited onto it and opaque.
  std::optional<glm::vec3> background;
};

struct RenderedView {
  Image color;  // [H, W, 4] sRGB-encoded RGB in [0, 1], straight alpha
  Image depth;  // [H, W, 1] camera z (OpenCV) of the first hit through the pixel centre; 0: none
};

// `view` only seeds the pixels' generators, so train and test views must pass distinct values.
RenderedView render_view(const Mesh& mesh, const RayTracer& tracer, const Lighting& lighting,
                         const Camera& camera, const RenderSettings& settings, unsigned view);

float linear_to_srgb(float linear);

}  // namespace splat::raytrace
