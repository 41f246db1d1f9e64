// The slow, obviously-correct rasterizer that the tiled one is tested against.
#include <algorithm>
#include <cmath>
#include <numeric>

#include "tests/raster/reference_rasterizer.hpp"

#include "splat/composite/composite.hpp"
#include "splat/raster/raster_constants.hpp"

namespace splat::test {

void render_reference(const GaussianModel& model, const Camera& camera,
                      const RenderSettings& settings, RenderResult& result,
                      std::vector<std::uint32_t>* last_blended_id) {
  check_render_inputs(model, camera);
  result.resize(camera.width, camera.height);
  if (last_blended_id) last_blended_id->assign(result.alpha.size(), kNoGaussian);
  ProjectedGaussians projected;
  project_gaussians(model, camera, settings.sh_degree, projected);
  const TileGrid grid = TileGrid::for_image(camera.width, camera.height);

  std::vector<std::uint32_t> order;  // visible Gaussians, front to back, ties by index
  for (std::size_t i = 0; i < projected.splats.size(); ++i)
    if (projected.radius[i] > 0) order.push_back(std::uint32_t(i));
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return projected.splats[a].depth < projected.splats[b].depth;
  });

  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      const int tile_x = x / kTileSize, tile_y = y / kTileSize;
      auto accum = CompositeAccum<float>::start();
      bool finished = false;
      std::uint32_t position = 0, last_blended = 0, last_id = kNoGaussian;
      for (std::uint32_t id : order) {
        const Splat2D& s = projected.splats[id];
        const TileRect rect = reference_tile_rect(s.mean_x, s.mean_y, projected.radius[id], grid);
        if (tile_x < rect.x0 || tile_x >= rect.x1 || tile_y < rect.y0 || tile_y >= rect.y1)
          continue;
        ++position;  // counts list entries as the tile's list would
        const float dx = s.mean_x - float(x), dy = s.mean_y - float(y);
        const float power =
            -0.5f * (s.conic_a * dx * dx + s.conic_c * dy * dy) - s.conic_b * dx * dy;
        const float alpha = std::min(kMaxAlpha, s.opacity * std::exp(power));
        const bool contributes = power <= 0.0f && alpha >= kMinAlpha;
        if (composite_step(accum, contributes, alpha, s.color[0], s.color[1], s.color[2],
                           s.depth, finished)) {
          last_blended = position;
          last_id = id;
        }
        if (finished) break;
      }
      const std::size_t p = std::size_t(y) * camera.width + x;
      for (int c = 0; c < 3; ++c)
        result.color.data[3 * p + c] = composite_finish(accum, c, settings.background[c]);
      result.alpha[p] = 1.0f - accum.transmittance;
      result.depth[p] = accum.depth;
      result.final_transmittance[p] = accum.transmittance;
      result.contributor_count[p] = last_blended;
      if (last_blended_id) (*last_blended_id)[p] = last_id;
    }
  }
}

}  // namespace splat::test
