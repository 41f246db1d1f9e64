#pragma once
// A photograph's exposure and white balance as an affine map of each colour channel, forward
// and backward side by side:
//   out_c = exp(a_c)·x_c + b_c,   c = R, G, B,
// with the parameters (a_R, a_G, a_B, b_R, b_G, b_B). Phone cameras set exposure and white
// balance per frame; a model that must match every frame as it is explains the differences
// with floaters in front of the cameras. Training through this map lets each view's
// differences live in its six numbers instead (splat/train/exposure_compensation.hpp).
#include <cmath>
#include <cstddef>

namespace splat {

constexpr int kExposureValues = 6;

// out = the map applied to `x`, both [pixels, 3] interleaved (may be the same array).
template <typename T>
void apply_exposure(const T* params, const T* x, T* out, std::size_t pixels) {
  const T gain[3] = {std::exp(params[0]), std::exp(params[1]), std::exp(params[2])};
  for (std::size_t p = 0; p < pixels; ++p)
    for (int c = 0; c < 3; ++c) out[3 * p + c] = gain[c] * x[3 * p + c] + params[3 + c];
}

// From ∂L/∂out (`v_out`): `v_x` receives ∂L/∂x (may be the same array as v_out) and
// `v_params` ∂L/∂params. `x` is the forward's input. Sums run in double in a fixed order.
template <typename T>
void apply_exposure_vjp(const T* params, const T* x, const T* v_out, T* v_x, T* v_params, std::size_t pixels) {
  const T gain[3] = {std::exp(params[0]), std::exp(params[1]), std::exp(params[2])};
  double v_gain[3] = {0, 0, 0}, v_bias[3] = {0, 0, 0};
  for (std::size_t p = 0; p < pixels; ++p)
    for (int c = 0; c < 3; ++c) {
      const T v = v_out[3 * p + c];
      v_gain[c] += double(v) * double(x[3 * p + c]);
      v_bias[c] += double(v);
      v_x[3 * p + c] = gain[c] * v;
    }
  for (int c = 0; c < 3; ++c) {
    v_params[c] = T(v_gain[c] * double(gain[c]));  // ∂out/∂a = exp(a)·x
    v_params[3 + c] = T(v_bias[c]);
  }
}

}  // namespace splat
