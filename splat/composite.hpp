#pragma once
// The one front-to-back compositor shared by the Gaussian rasterizer and the NeRF
// (DESIGN.md, "One compositor"):
//   C = Σᵢ Tᵢ αᵢ cᵢ + T_N · bg,   Tᵢ = Πⱼ<ᵢ (1 − αⱼ),
// with early termination: a sample that would drop T below kMinTransmittance is not
// blended and ends the pixel (ray), exactly as the reference 3DGS rasterizer does.
//
// Templated on the float type F and mask type M so one definition serves a single ray
// (F = float/double, M = bool) and kLanes pixels at once (F = simd::f32v, M = simd::i32v).
// It is a header so the compiler inlines it into the per-pixel hot loop.
#include "splat/core/simd.hpp"

namespace splat {

// Stop before the transmittance falls below this.
constexpr float kMinTransmittance = 1e-4f;

// Running sums of one pixel or ray (or a batch of them, lane-wise).
template <class F>
struct CompositeAccum {
  F transmittance;  // T: product of (1 − α) over the samples blended so far
  F color[3];       // Σ Tᵢ αᵢ cᵢ
  F depth;          // Σ Tᵢ αᵢ zᵢ (expected depth, not normalised by the accumulated alpha)

  static CompositeAccum start() {
    CompositeAccum a;
    a.transmittance = F{} + 1.0f;
    a.color[0] = a.color[1] = a.color[2] = F{};
    a.depth = F{};
    return a;
  }
};

// Offers one sample (α, colour, depth) to the lanes in `contributes`. Lanes where the
// sample would push T below kMinTransmittance are added to `finished` and left unchanged;
// the others blend it. Returns the lanes that blended.
template <class F, class M>
inline M composite_step(CompositeAccum<F>& acc, M contributes, F alpha, F red, F green, F blue,
                        F depth, M& finished) {
  using simd::mask_and;
  using simd::mask_and_not;
  using simd::select;
  const F next_transmittance = acc.transmittance * (1.0f - alpha);
  const M stops = mask_and(contributes, M(next_transmittance < kMinTransmittance));
  const M blends = mask_and_not(contributes, stops);
  const F weight = alpha * acc.transmittance;
  acc.color[0] = select(blends, acc.color[0] + red * weight, acc.color[0]);
  acc.color[1] = select(blends, acc.color[1] + green * weight, acc.color[1]);
  acc.color[2] = select(blends, acc.color[2] + blue * weight, acc.color[2]);
  acc.depth = select(blends, acc.depth + depth * weight, acc.depth);
  acc.transmittance = select(blends, next_transmittance, acc.transmittance);
  finished = simd::mask_or(finished, stops);
  return blends;
}

// Final colour of a channel: the blended sum plus the background seen through what is left.
template <class F>
inline F composite_finish(const CompositeAccum<F>& acc, int channel, float background) {
  return acc.color[channel] + acc.transmittance * background;
}

}  // namespace splat
