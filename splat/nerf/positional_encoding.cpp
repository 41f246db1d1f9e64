#include "splat/nerf/positional_encoding.hpp"

#include <cmath>
#include <numbers>

namespace splat {
namespace {

// ωₖ = 2ᵏπ rounded once to Scalar: scaling by a power of two is exact, so every ωₖ is
// exactly 2ᵏ·Scalar(π) and forward and VJP see the same arguments ωₖ·p.
template <typename Scalar>
Scalar angular_frequency(int k) {
  return std::ldexp(Scalar(std::numbers::pi), k);
}

// Frequencies computed with sin and cos; the ones between come from the one below by the
// double-angle formulas (a fifth of the cost). Each doubling at most doubles the error, so
// after three it is 8 units in the last place, the size of the error the rounded argument
// 2ᵏπ·p of the direct evaluation already carries at those frequencies.
constexpr int kExactEvery = 4;

}  // namespace

template <typename Scalar>
void encode(const Scalar* xyz, int frequencies, Scalar* out) {
  out[0] = xyz[0];
  out[1] = xyz[1];
  out[2] = xyz[2];
  Scalar* sines = out + 3;
  for (int k = 0; k < frequencies; ++k, sines += 6) {
    if (k % kExactEvery == 0) {
      const Scalar omega = angular_frequency<Scalar>(k);
      for (int c = 0; c < 3; ++c) {
        const Scalar angle = omega * xyz[c];
        sines[c] = std::sin(angle);
        sines[3 + c] = std::cos(angle);
      }
      continue;
    }
    // The double angle from the frequency below: sin 2a = 2 sin a cos a,
    // cos 2a = (cos a − sin a)(cos a + sin a).
    for (int c = 0; c < 3; ++c) {
      const Scalar s = sines[c - 6], co = sines[3 + c - 6];
      sines[c] = Scalar(2) * s * co;
      sines[3 + c] = (co - s) * (co + s);
    }
  }
}

template <typename Scalar>
void encode_vjp(const Scalar* xyz, int frequencies, const Scalar* v_out, Scalar* v_xyz) {
  Scalar v[3] = {v_out[0], v_out[1], v_out[2]};
  const Scalar* v_sines = v_out + 3;
  for (int k = 0; k < frequencies; ++k, v_sines += 6) {
    const Scalar omega = angular_frequency<Scalar>(k);
    for (int c = 0; c < 3; ++c) {
      const Scalar angle = omega * xyz[c];
      // d sin(ωp) = ω cos(ωp) dp;  d cos(ωp) = −ω sin(ωp) dp.
      v[c] += omega * (v_sines[c] * std::cos(angle) - v_sines[3 + c] * std::sin(angle));
    }
  }
  v_xyz[0] += v[0];
  v_xyz[1] += v[1];
  v_xyz[2] += v[2];
}

template <typename Scalar>
void encode_batch(const Scalar* xyz, std::size_t count, int frequencies, Scalar* out) {
  const std::size_t size = std::size_t(encoded_size(frequencies));
  for (std::size_t i = 0; i < count; ++i) encode(xyz + 3 * i, frequencies, out + size * i);
}

template <typename Scalar>
void encode_batch_vjp(const Scalar* xyz, std::size_t count, int frequencies,
                      const Scalar* v_out, Scalar* v_xyz) {
  const std::size_t size = std::size_t(encoded_size(frequencies));
  for (std::size_t i = 0; i < count; ++i)
    encode_vjp(xyz + 3 * i, frequencies, v_out + size * i, v_xyz + 3 * i);
}

template void encode<float>(const float*, int, float*);
template void encode<double>(const double*, int, double*);
template void encode_vjp<float>(const float*, int, const float*, float*);
template void encode_vjp<double>(const double*, int, const double*, double*);
template void encode_batch<float>(const float*, std::size_t, int, float*);
template void encode_batch<double>(const double*, std::size_t, int, double*);
template void encode_batch_vjp<float>(const float*, std::size_t, int, const float*, float*);
template void encode_batch_vjp<double>(const double*, std::size_t, int, const double*,
                                       double*);

}  // namespace splat
