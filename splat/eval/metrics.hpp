#pragma once
// Image quality metrics, on images with values in [0, 1].
#include "splat/core/image.hpp"

namespace splat {

// Peak signal-to-noise ratio over all channels and pixels: −10·log10(MSE); +inf when equal.
// Throws ArgumentError when the images differ in size or channel count.
double psnr(const Image& a, const Image& b);

}  // namespace splat
