#pragma once
// The training loss over the pixels a mask keeps (nerfstudio's per-image masks), forward and
// backward side by side:
//   L_m(r) = L(r ⊙ m, t ⊙ m),   ∂L_m/∂r = m ⊙ ∂L/∂(r ⊙ m)
// with L the photometric loss (photometric_loss.hpp) and m a weight per pixel in [0, 1], the
// same for the three channels. Where m = 0 the render and the photograph are both 0, so the
// pixel adds nothing to L1 and its render gets no gradient: what the photo shows there (a
// person walking by, the turntable) is neither learnt nor punished. SSIM's windows that
// straddle a mask's edge see its zeros on both sides alike, as nerfstudio's splatfacto does.
#include <vector>

#include "splat/core/image.hpp"
#include "splat/optim/photometric_loss.hpp"

namespace splat {

struct MaskedLossScratch {
  std::vector<float> masked;  // the render and the photograph through the mask
  SsimScratch ssim;
};

// `mask` is [H, W, 1] for the [H, W, 3] `rendered` and `target`; `v_rendered`, if not null,
// receives ∂L_m/∂rendered. Deterministic for any thread count; ArgumentError for mismatched
// shapes.
LossValue masked_photometric_loss(const Image& rendered, const Image& target, const Image& mask,
                                  float ssim_weight, Image* v_rendered, MaskedLossScratch& scratch);

// The scalar-generic core on raw arrays (float for training, double for the tests' finite
// differences); `masked` holds 2·H·W·3 values of scratch.
template <typename T>
LossValue masked_photometric_loss_core(const T* rendered, const T* target, const T* mask, int width, int height,
                                       T ssim_weight, T* v_rendered, std::vector<T>& masked,
                                       std::vector<T>& buffers);

}  // namespace splat
