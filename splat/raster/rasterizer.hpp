#pragma once
// The tile-based CPU rasterizer: project → bin and sort → blend. It owns its scratch buffers
// so that rendering many frames (or training iterations) allocates nothing after the first.
#include "splat/core/camera.hpp"
#include "splat/gaussians/gaussian_model.hpp"
#include "splat/raster/bin_sort.hpp"
#include "splat/raster/project.hpp"
#include "splat/raster/render_result.hpp"

namespace splat {

struct RenderSettings {
  int sh_degree = kMaxShDegree;         // bands used; clamped to the model's degree
  float background[3] = {1, 1, 1};      // composited with the final transmittance
};

// Wall time of each stage of the last render, in milliseconds.
struct RenderTimings {
  double project_ms = 0, bin_sort_ms = 0, blend_ms = 0;
  double total_ms() const { return project_ms + bin_sort_ms + blend_ms; }
};

class Rasterizer {
 public:
  // Renders `model` as seen by `camera` into `result` (resized to the camera's image).
  // Throws ArgumentError for an inconsistent model or a camera without pixels.
  void render(const GaussianModel& model, const Camera& camera, const RenderSettings& settings,
              RenderResult& result);

  const RenderTimings& last_timings() const { return timings_; }
  // The intermediate state of the last render, which the backward pass reuses.
  const ProjectedGaussians& projected() const { return projected_; }
  const TileBins& bins() const { return bins_; }
  const TileGrid& grid() const { return grid_; }

 private:
  ProjectedGaussians projected_;
  TileBins bins_;
  TileGrid grid_;
  RenderTimings timings_;
};

// The test oracle: every pixel over every Gaussian in depth order, no tiles, no SIMD, libm
// exp. It honours the reference rasterizer's tile-rectangle clipping (a Gaussian reaches a
// pixel only if the pixel's tile lies in its radius rectangle), so it defines exactly what
// the tiled renderer must produce. Slow: for small tests only.
// `last_blended_id`, if given, receives per pixel the index of the last Gaussian blended
// (kNoGaussian if none), to check the tiled renderer's contributor_count.
constexpr std::uint32_t kNoGaussian = 0xffffffffu;
void render_reference(const GaussianModel& model, const Camera& camera,
                      const RenderSettings& settings, RenderResult& result,
                      std::vector<std::uint32_t>* last_blended_id = nullptr);

// Throws ArgumentError for an inconsistent model or a camera without pixels.
void check_render_inputs(const GaussianModel& model, const Camera& camera);

}  // namespace splat
