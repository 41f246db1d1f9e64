#pragma once
// The 3DGS training loss and the SSIM metric, forward and backward side by side.
//   L = (1 − λ)·L1 + λ·(1 − SSIM),  λ = 0.2
// L1 is the mean absolute difference over all pixels and channels; SSIM is the mean of the
// SSIM map computed per channel with an 11×11 Gaussian window (σ = 1.5), zero padding at the
// border (as the official code's conv2d with padding 5), C1 = 0.01², C2 = 0.03² (ssim.hpp has
// the definition, the derivation of its backward and the constants).
#include <vector>

#include "splat/core/image.hpp"

namespace splat {

constexpr float kDefaultSsimWeight = 0.2f;  // λ

// Reusable buffers so a training step allocates nothing after the first: SSIM's saved state
// for the backward (three values per pixel and channel) and a small workspace per thread.
struct SsimScratch {
  std::vector<float> buffers;  // layout private to the implementation (ssim.cpp)
};

struct LossValue {
  double loss = 0;  // (1 − λ)·L1 + λ·(1 − SSIM)
  double l1 = 0;
  double ssim = 0;
};

// Loss of `rendered` against `target` (same shape, 3 channels). If `v_rendered` is not null it
// receives ∂L/∂rendered (resized to the image's shape). Deterministic for any thread count.
// The gradient of L1 is sign(rendered − target)/n (n = H·W·3), taken as 0 where they are equal.
// Throws ArgumentError when the shapes differ, the images are empty or not 3-channel.
LossValue photometric_loss(const Image& rendered, const Image& target, float ssim_weight,
                           Image* v_rendered, SsimScratch& scratch);

// Mean SSIM of two images (the evaluation metric; same definition as in the loss). Any channel
// count, equal in both; throws ArgumentError when the shapes differ or the images are empty.
double ssim(const Image& a, const Image& b);

// The scalar-generic core of photometric_loss, on raw interleaved [height, width, 3] arrays;
// `v_rendered`, if not null, is overwritten with ∂L/∂rendered. No shape checks. Instantiated for
// float (what photometric_loss runs) and double (the tests' finite differences).
template <typename T>
LossValue photometric_loss_core(const T* rendered, const T* target, int width, int height,
                                T ssim_weight, T* v_rendered, std::vector<T>& buffers);

}  // namespace splat
