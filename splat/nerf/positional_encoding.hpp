#pragma once
// NeRF's positional encoding (Mildenhall et al. 2020, eq. 4), with the raw input kept:
//   γ(p) = (p, sin(2⁰πp), cos(2⁰πp), …, sin(2^{L−1}πp), cos(2^{L−1}πp))
// for p = (x, y, z) and L frequencies. Exact order of the 3 + 6L outputs, as the reference
// NeRF code concatenates them (identity, then per frequency all sines, then all cosines):
//   x y z,  sin(ω₀x) sin(ω₀y) sin(ω₀z),  cos(ω₀x) cos(ω₀y) cos(ω₀z),  sin(ω₁x) …,  with ωₖ = 2ᵏπ.
// (The reference code drops π from ωₖ; the paper and this code keep it.) Every fourth
// frequency is evaluated with sin and cos, the ones between by the double-angle formulas.
//
// One sample's code is contiguous, so a batch of N codes is a column-major [3 + 6L, N]
// matrix: the right operand of the MLP's first product W·Γ.
//
// Templated on the scalar so the gradient tests run in double; instantiated for float and
// double in positional_encoding.cpp.
#include <cstddef>

namespace splat {

// Frequencies beyond this give arguments 2ᵏπp whose float rounding alone exceeds a period.
constexpr int kMaxEncodingFrequencies = 24;

// 3 + 6L: the raw coordinates plus one sine and one cosine per coordinate and frequency.
constexpr int encoded_size(int frequencies) { return 3 + 6 * frequencies; }

// out[encoded_size(frequencies)] = γ(xyz[3]).
template <typename Scalar>
void encode(const Scalar* xyz, int frequencies, Scalar* out);

// v_xyz[3] += (∂γ/∂xyz)ᵀ · v_out[encoded_size(frequencies)]. Per coordinate p:
//   ∂p/∂p = 1,  ∂sin(ωp)/∂p = ω cos(ωp),  ∂cos(ωp)/∂p = −ω sin(ωp),
// so v_p += v_p,raw + Σₖ ωₖ (v_sin,k cos(ωₖp) − v_cos,k sin(ωₖp)).
template <typename Scalar>
void encode_vjp(const Scalar* xyz, int frequencies, const Scalar* v_out, Scalar* v_xyz);

// Batched: xyz [count, 3] interleaved → out [count, encoded_size] (sample-major, i.e. the
// column-major [encoded_size, count] matrix the MLP multiplies).
template <typename Scalar>
void encode_batch(const Scalar* xyz, std::size_t count, int frequencies, Scalar* out);

// Batched VJP: v_xyz [count, 3] += per sample encode_vjp of v_out [count, encoded_size].
template <typename Scalar>
void encode_batch_vjp(const Scalar* xyz, std::size_t count, int frequencies,
                      const Scalar* v_out, Scalar* v_xyz);

}  // namespace splat
