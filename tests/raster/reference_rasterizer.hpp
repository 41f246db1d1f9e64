#pragma once
// The slow, obviously-correct rasterizer that the tiled one is tested against.
#include <cstdint>
#include <vector>

#include "splat/raster/rasterizer.hpp"

namespace splat::test {

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

}  // namespace splat::test
