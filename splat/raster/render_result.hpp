#pragma once
// What one render produces: the image and the per-pixel state the backward pass needs.
#include <cstdint>
#include <vector>

#include "splat/core/image.hpp"

namespace splat {

struct RenderResult {
  Image color;                                   // [H, W, 3] with background, not clamped
  std::vector<float> alpha;                      // [H, W] 1 − final transmittance
  std::vector<float> depth;                      // [H, W] Σ wᵢ zᵢ (divide by alpha to normalise)
  std::vector<float> final_transmittance;        // [H, W] T after the last blended Gaussian
  std::vector<std::uint32_t> contributor_count;  // [H, W] entries of the pixel's tile list
                                                 // up to and including its last blended one

  void resize(int width, int height) {
    if (color.width != width || color.height != height || color.channels != 3)
      color = Image(width, height, 3);
    const std::size_t pixels = std::size_t(width) * height;
    alpha.resize(pixels);
    depth.resize(pixels);
    final_transmittance.resize(pixels);
    contributor_count.resize(pixels);
  }
};

}  // namespace splat
