#pragma once
// One NeRF ray through the shared compositor (splat/composite/composite.hpp), forward and backward,
// templated on the float type so the gradient tests run it in double.
//
// The NeRF's own rule is α = min(0.99, 1 − exp(−σδ)) with no small-α skip (the skip at
// 1/255 is the rasterizer's alone; the cap is shared, see density_to_alpha). What the
// compositor does for both is the sum C = Σ Tᵢαᵢcᵢ + T_N·bg and the early stop: a sample
// that would take T below kMinTransmittance is not blended and ends the ray. Because no
// sample is skipped, the blended samples of a ray are always a prefix of its list:
// [0, blended_count).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "splat/composite/composite.hpp"

namespace splat {

// α = min(kMaxAlpha, 1 − exp(−σδ)), the exponential as −expm1(−σδ) so that small σδ keep
// their digits. The cap is the compositor's, shared with the rasterizer, for one reason: the
// compositor stops *before* a sample that would take T below kMinTransmittance, so an
// unclamped opaque sample (σδ > 9.2) met at T = 1 would never be blended: the ray would show
// the background behind a solid surface, and that sample would get no gradient to learn
// otherwise. With α ≤ 0.99 two opaque samples take T to 1e-4 and the surface shows.
template <class F>
inline F density_to_alpha(F sigma, F delta) {
  return std::min(F(kMaxAlpha), F(-std::expm1(-sigma * delta)));
}

// ∂α/∂σ = δ·exp(−σδ) (= δ(1 − α)) below the cap, zero where the cap holds (as the splat
// trainer's exact gradient at the same clamp). δ is a constant: no gradient to positions.
template <class F>
inline F density_to_alpha_vjp(F sigma, F delta, F v_alpha) {
  if (-std::expm1(-sigma * delta) > F(kMaxAlpha)) return F(0);
  return v_alpha * delta * std::exp(-sigma * delta);
}

// What one ray composites to, and what its backward needs.
template <class F>
struct RayComposite {
  F color[3];                   // Σ Tᵢαᵢcᵢ + T_N·bg
  F alpha;                      // 1 − T_N
  F depth;                      // Σ Tᵢαᵢtᵢ: expected distance, not normalised by alpha
  F final_transmittance;        // T_N, after the last blended sample
  std::uint32_t blended_count;  // samples [0, blended_count) were blended
};

// Composites n samples, front to back: alpha [n], rgb [n, 3], t [n] (the depth of each
// sample). Writes weights [n] = Tᵢαᵢ (0 for the samples past the early stop) when
// `weights` is not null.
template <class F>
inline RayComposite<F> composite_ray(std::size_t n, const F* alpha, const F* rgb, const F* t,
                                     const F background[3], F* weights) {
  auto accum = CompositeAccum<F>::start();
  bool finished = false;
  std::size_t i = 0;
  for (; i < n; ++i) {
    const F transmittance_before = accum.transmittance;
    if (!composite_step(accum, true, alpha[i], rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2], t[i],
                        finished))
      break;  // the T floor: this sample and all behind it are not blended
    // The same product (α·T) the compositor blended with.
    if (weights) weights[i] = alpha[i] * transmittance_before;
  }
  if (weights)
    for (std::size_t k = i; k < n; ++k) weights[k] = F(0);
  RayComposite<F> out;
  for (int c = 0; c < 3; ++c) out.color[c] = composite_finish(accum, c, background[c]);
  out.alpha = F(1) - accum.transmittance;
  out.depth = accum.depth;
  out.final_transmittance = accum.transmittance;
  out.blended_count = std::uint32_t(i);
  return out;
}

// Backward of composite_ray's colour: given v_color = ∂L/∂color [3], writes
// v_alpha [n] = ∂L/∂αᵢ and v_rgb [n, 3] = ∂L/∂cᵢ, walking back from the last blended sample
// through the compositor's backward; samples past the early stop get zeros. (The alpha and
// depth outputs carry no cotangent here.)
template <class F>
inline void composite_ray_vjp(std::size_t n, const F* alpha, const F* rgb,
                              const RayComposite<F>& forward, const F background[3],
                              const F v_color[3], F* v_alpha, F* v_rgb) {
  // bg·v summed in the order the rasterizer's backward sums it.
  F background_dot_v{};
  for (int c = 0; c < 3; ++c) background_dot_v += background[c] * v_color[c];
  auto reverse = CompositeReverse<F>::start(forward.final_transmittance);
  for (std::size_t i = forward.blended_count; i-- > 0;)
    composite_step_vjp(reverse, true, alpha[i], rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2],
                       v_color, forward.final_transmittance, background_dot_v, v_alpha[i],
                       &v_rgb[3 * i]);
  for (std::size_t i = forward.blended_count; i < n; ++i) {
    v_alpha[i] = F(0);
    v_rgb[3 * i] = v_rgb[3 * i + 1] = v_rgb[3 * i + 2] = F(0);
  }
}

}  // namespace splat
