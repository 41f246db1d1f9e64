#pragma once
// The 8-bit encodings the web formats (.splat, .spz) share: a value rounded to the nearest
// byte, an opacity as 255·sigmoid(logit), and the unit quaternion they store.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "splat/core/activations.hpp"
#include "splat/gaussians/covariance.hpp"

namespace splat {

// `value` rounded to the nearest integer and clamped to 0..255.
inline std::uint8_t to_byte(float value) {
  return static_cast<std::uint8_t>(std::clamp(std::round(value), 0.0f, 255.0f));
}

// The opacity logit of an opacity stored as byte / 255. Bytes 0 and 255 stand for opacities
// within half a step of 0 and 1, whose logits are infinite: they read as 0.5 / 255 and
// 254.5 / 255, which round back to the same bytes.
inline float opacity_logit_from_byte(std::uint8_t byte) {
  const float p = std::clamp(float(byte), 0.5f, 254.5f) / 255.0f;
  return logit(p);
}

// The quaternion (w, x, y, z) scaled to unit length; a zero quaternion stays zero.
inline Vec4<float> unit_quaternion(const Vec4<float>& q) {
  const float length = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  return length > 0 ? q / length : q;
}

}  // namespace splat
