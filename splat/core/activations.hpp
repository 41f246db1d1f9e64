#pragma once
// The activations that turn stored parameters into the values they stand for, written once:
// a Gaussian's opacity = sigmoid(logit) and its inverse (docs/DESIGN.md §3.2), and the NeRF's
// colour head. They live in core because the Gaussians and the NeRF, one layer up and side by
// side, both use them.
//
// Each is this exact expression in the argument's precision (float for training, as the
// official trainer's activations run on the GPU; double in the gradient tests): trained models
// depend on every bit of it, so no faster approximation stands in for it anywhere.
#include <cmath>
#include <concepts>

#include "splat/core/simd.hpp"

namespace splat {

// σ(x) = 1 / (1 + e⁻ˣ).
template <std::floating_point T>
T sigmoid(T x) {
  return T(1) / (T(1) + std::exp(-x));
}

// σ⁻¹(p) = log(p / (1 − p)), the logit of a probability (an opacity) in (0, 1).
template <std::floating_point T>
T logit(T p) {
  return std::log(p / (T(1) - p));
}

namespace simd {

// σ per lane: in every lane the scalar sigmoid's value (libm's exp, lane by lane).
inline f32v sigmoid(f32v x) {
  return 1.0f / (1.0f + per_lane(-x, [](float v) { return std::exp(v); }));
}

}  // namespace simd

}  // namespace splat
