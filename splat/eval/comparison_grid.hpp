#pragma once
// Side-by-side comparison images for splat-eval: ground truth | each method's render | each
// method's error, one row, each panel the size of the ground truth.
#include <vector>

#include "splat/core/image.hpp"

namespace splat {

// How much the error maps are amplified: a per-pixel absolute error e (mean over the RGB
// channels, in [0, 1]) is shown as grey min(1, kErrorMapGain·e). Errors of a few percent are
// typical of a trained model, so an unscaled map would look black.
constexpr float kErrorMapGain = 4.0f;

// Grey RGB image of min(1, kErrorMapGain · mean_c |a − b|). Throws ArgumentError when the
// images differ in size or are not RGB.
Image error_map(const Image& a, const Image& b);

// The panels left to right in one RGB image (each panel clamped to [0, 1]); all panels must
// be RGB and of one size (ArgumentError otherwise).
Image concatenate_horizontally(const std::vector<const Image*>& panels);

// ground truth | renders[0] | renders[1] | ... | error_map(renders[0]) | error_map(renders[1]) | ...
Image comparison_grid(const Image& truth, const std::vector<const Image*>& renders);

}  // namespace splat
