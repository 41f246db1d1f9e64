#pragma once
// The one front-to-back compositor shared by the Gaussian rasterizer and the NeRF
// (docs/DESIGN.md, "One compositor"):
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
// No sample is more opaque than this: the rasterizer's α = min(kMaxAlpha, o·G) and the NeRF's
// α = min(kMaxAlpha, 1 − exp(−σδ)), as in the official 3DGS rasterizer.
constexpr float kMaxAlpha = 0.99f;

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
template <class F, class Scalar>
inline F composite_finish(const CompositeAccum<F>& acc, int channel, Scalar background) {
  return acc.color[channel] + acc.transmittance * background;
}

// ---- Backward -------------------------------------------------------------------------
// Walking the blended samples back to front, the transmittance in front of sample i is
// rebuilt from the one behind it, Tᵢ = Tᵢ₊₁ / (1 − αᵢ), starting from the saved final T.
// With Bᵢ = Σⱼ>ᵢ αⱼ cⱼ Πᵢ<ₖ<ⱼ (1 − αₖ) the colour composited behind i (per unit of Tᵢ₊₁):
//   ∂C/∂cᵢ = Tᵢ αᵢ
//   ∂C/∂αᵢ = Tᵢ (cᵢ − Bᵢ) − T_N / (1 − αᵢ) · bg
// and Bᵢ₋₁ = αᵢ cᵢ + (1 − αᵢ) Bᵢ. (The bg term: every Tⱼ, j > i, and T_N hold a factor (1 − αᵢ).)
// The loss needs Bᵢ only through v·Bᵢ (v = ∂L/∂C, the same for every sample of the pixel),
// which follows the same recurrence: one running sum instead of three.

template <class F>
struct CompositeReverse {
  F transmittance;  // Tᵢ₊₁ while undoing sample i: starts at the final T
  F behind_dot_v;   // v·Bᵢ: starts at 0

  static CompositeReverse start(F final_transmittance) {
    CompositeReverse r;
    r.transmittance = final_transmittance;
    r.behind_dot_v = F{};
    return r;
  }
};

// Undoes one sample in the lanes of `blended` (the lanes where the forward pass blended it),
// given the pixel's colour cotangent v_pixel and the constants T_N and bg·v_pixel. Writes
// ∂L/∂α and ∂L/∂c for the sample (zero in the other lanes) and returns its blending weight
// Tᵢαᵢ (zero in the other lanes), which density control reads as how much the pixel saw of it.
template <class F, class M>
inline F composite_step_vjp(CompositeReverse<F>& r, M blended, F alpha, F red, F green, F blue,
                               const F v_pixel[3], F final_transmittance, F background_dot_v,
                               F& v_alpha, F v_color[3]) {
  using simd::select;
  const F one_minus_alpha = 1.0f - alpha;
  const F transmittance = r.transmittance / one_minus_alpha;  // Tᵢ
  const F weight = alpha * transmittance;
  const F color[3] = {red, green, blue};
  F color_dot_v = F{};
  for (int c = 0; c < 3; ++c) {
    v_color[c] = select(blended, weight * v_pixel[c], F{});
    color_dot_v = color_dot_v + color[c] * v_pixel[c];
  }
  v_alpha = select(blended,
                   transmittance * (color_dot_v - r.behind_dot_v) - final_transmittance / one_minus_alpha * background_dot_v,
                   F{});
  r.behind_dot_v = select(blended, alpha * color_dot_v + one_minus_alpha * r.behind_dot_v, r.behind_dot_v);
  r.transmittance = select(blended, transmittance, r.transmittance);
  return select(blended, weight, F{});
}

}  // namespace splat
