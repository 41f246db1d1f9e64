#pragma once
// The 3DGS training loss and the SSIM metric, forward and backward side by side.
//   L = (1 − λ)·L1 + λ·(1 − SSIM),  λ = 0.2
// L1 is the mean absolute difference over all pixels and channels; SSIM is the mean of the
// SSIM map computed per channel with an 11×11 Gaussian window (σ = 1.5), zero padding at the
// border (as the official code's conv2d with padding 5), C1 = 0.01², C2 = 0.03².
#include <vector>

#include "splat/core/image.hpp"

namespace splat {

constexpr float kDefaultSsimWeight = 0.2f;  // λ

// Reusable buffers so a training step allocates nothing after the first.
struct SsimScratch {
  std::vector<float> buffers;  // layout private to the implementation
};

struct LossValue {
  double loss = 0;  // (1 − λ)·L1 + λ·(1 − SSIM)
  double l1 = 0;
  double ssim = 0;
};

// Loss of `rendered` against `target` (same shape, 3 channels). If `v_rendered` is not null it
// receives ∂L/∂rendered (resized to the image's shape). Deterministic for any thread count.
LossValue photometric_loss(const Image& rendered, const Image& target, float ssim_weight,
                           Image* v_rendered, SsimScratch& scratch);

// Mean SSIM of two images (the evaluation metric; same definition as in the loss).
double ssim(const Image& a, const Image& b);

}  // namespace splat
