#pragma once
// Scoring where every photograph has its own light (NeRF-W's protocol): a model without
// per-photo appearance cannot know a test photo's exposure, and a model with it has no code
// for a test view. Both are scored the same way: a per-channel gain and offset mapping the
// render onto the photo is fitted by least squares on the photo's left half (columns
// x < width/2), and the PSNR of the mapped render is taken over the right half only, which
// the fit never saw.
#include "splat/core/image.hpp"

namespace splat {

// The half-fitted PSNR of `render` against `photo` (same shape, values in [0, 1]; the mapped
// render is clamped to [0, 1]). +inf when the right half is matched exactly. Throws
// ArgumentError when the shapes differ or the image is narrower than 2 pixels.
double half_fitted_psnr(const Image& render, const Image& photo);

}  // namespace splat
