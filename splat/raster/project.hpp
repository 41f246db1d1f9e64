#pragma once
// Stage 1 of the rasterizer: every Gaussian to its screen-space footprint and colour.
#include <cstdint>
#include <vector>

#include "splat/core/camera.hpp"
#include "splat/gaussians/gaussian_model.hpp"

namespace splat {

// What blending needs of one Gaussian, packed into 52 bytes so a tile's pass over its list
// touches one or two cache lines per Gaussian.
struct Splat2D {
  float mean_x, mean_y;              // pixel coordinates, pixel centres at integers
  float conic_a, conic_b, conic_c;   // Σ'⁻¹ = [[a, b], [b, c]]
  float opacity;                     // sigmoid(opacity logit)
  float color[3];                    // SH colour + 0.5, clamped at 0
  float depth;                       // camera-space z
  float extent_x, extent_y;          // half-size of the box outside which α < kMinAlpha
  float q_max;                       // α ≥ kMinAlpha needs dᵀΣ'⁻¹d ≤ q_max = 2 ln(o / kMinAlpha)
};

// Tiles [x0, x1) x [y0, y1) a Gaussian is binned into. Empty when x0 == x1 or y0 == y1.
struct TileRect {
  std::int32_t x0, y0, x1, y1;
  std::int64_t count() const { return std::int64_t(x1 - x0) * (y1 - y0); }
};

struct ProjectedGaussians {
  std::vector<Splat2D> splats;     // [N]
  std::vector<std::int32_t> radius;  // [N] reference screen radius in px, 0 when culled
  std::vector<TileRect> tiles;     // [N] the tiles each Gaussian is blended in
};

struct TileGrid {
  int tiles_x = 0, tiles_y = 0;
  int count() const { return tiles_x * tiles_y; }
  static TileGrid for_image(int width, int height);
};

// Rectangle of tiles the reference rasterizer assigns to a splat of screen radius r centred
// at (x, y). The tiled renderer bins into its intersection with the α ≥ kMinAlpha box.
TileRect reference_tile_rect(float x, float y, int r, const TileGrid& grid);

// Projects every Gaussian of `model` for `camera`, colour from SH bands up to `sh_degree`
// (clamped to the model's). Culls Gaussians at or behind the near plane, with a singular
// 2D covariance, or touching no tile. Parallel over Gaussians; the result does not depend
// on the thread count.
void project_gaussians(const GaussianModel& model, const Camera& camera, int sh_degree,
                       ProjectedGaussians& out);

}  // namespace splat
