#pragma once
// Image quality metrics, on images with values in [0, 1].
#include "splat/core/image.hpp"

namespace splat {

// Peak signal-to-noise ratio over all channels and pixels: −10·log10(MSE); +inf when equal.
// Throws ArgumentError when the images differ in size or channel count.
double psnr(const Image& a, const Image& b);

// PSNR over the pixels a mask keeps: the squared errors weighted by `mask` ([H, W, 1] weights
// in [0, 1]) and divided by the channels times the masks's sum; +inf when equal there or when
// the mask keeps nothing. ArgumentError when the shapes differ.
double masked_psnr(const Image& a, const Image& b, const Image& mask);

// `image` with every channel multiplied by `mask` ([H, W, 1]): what the masked loss and the
// masked SSIM see.
Image masked(const Image& image, const Image& mask);

}  // namespace splat
