#pragma once
// Eight-lane float and mask vectors (GCC/Clang vector extensions). The compiler lowers them to
// AVX/AVX-512 with -march=native and to pairs of SSE registers otherwise, so the code stays
// portable while the hot loops run one instruction per eight pixels.
//
// The helpers below have scalar overloads too, so templated code (the shared compositor)
// runs unchanged on `float` + `bool` (one ray) or `f32x8` + `i32x8` (eight pixels).
#include <cstdint>
#include <cstring>

namespace splat::simd {

constexpr int kLanes = 8;
using f32x8 = float __attribute__((vector_size(32)));
using i32x8 = std::int32_t __attribute__((vector_size(32)));  // lanes are 0 or -1 (all bits)

// Lane-wise choice: where `mask` is set take `a`, else `b`.
inline f32x8 select(i32x8 mask, f32x8 a, f32x8 b) { return mask ? a : b; }
inline i32x8 select(i32x8 mask, i32x8 a, i32x8 b) { return mask ? a : b; }
inline float select(bool mask, float a, float b) { return mask ? a : b; }
inline double select(bool mask, double a, double b) { return mask ? a : b; }

inline i32x8 mask_and(i32x8 a, i32x8 b) { return a & b; }
inline i32x8 mask_and_not(i32x8 a, i32x8 b) { return a & ~b; }  // a and not b
inline i32x8 mask_or(i32x8 a, i32x8 b) { return a | b; }
inline bool mask_and(bool a, bool b) { return a && b; }
inline bool mask_and_not(bool a, bool b) { return a && !b; }
inline bool mask_or(bool a, bool b) { return a || b; }

inline bool any(i32x8 mask) {
  std::uint64_t words[4];
  std::memcpy(words, &mask, sizeof(mask));
  return (words[0] | words[1] | words[2] | words[3]) != 0;
}
inline bool any(bool mask) { return mask; }

inline int count(i32x8 mask) {
  int n = 0;
  for (int i = 0; i < kLanes; ++i) n += mask[i] != 0;
  return n;
}

inline f32x8 broadcast(float x) { return f32x8{} + x; }
inline f32x8 min(f32x8 a, f32x8 b) { return a < b ? a : b; }
inline f32x8 max(f32x8 a, f32x8 b) { return a > b ? a : b; }

// e^x for x <= 0, relative error below 2e-7 (a few ulp), flushing to 0 below -87.
// Cody-Waite range reduction x = n ln2 + r, |r| <= ln2/2, then a degree-6 Taylor-like
// minimax polynomial for e^r; 2^n is built in the exponent bits. Deterministic on every
// machine (no libm call), which keeps renders identical across platforms and thread counts.
inline f32x8 exp_nonpositive(f32x8 x) {
  constexpr float kLog2e = 1.44269504088896341f;
  constexpr float kLn2Hi = 0.693359375f;
  constexpr float kLn2Lo = -2.12194440e-4f;
  x = max(x, broadcast(-87.0f));
  const f32x8 n = __builtin_convertvector(
      __builtin_convertvector(x * kLog2e - 0.5f, i32x8), f32x8);  // round(x log2e): truncation of (x log2e - 0.5) for x <= 0
  const f32x8 r = (x - n * kLn2Hi) - n * kLn2Lo;
  f32x8 p = broadcast(1.9875691500e-4f);
  p = p * r + 1.3981999507e-3f;
  p = p * r + 8.3334519073e-3f;
  p = p * r + 4.1665795894e-2f;
  p = p * r + 1.6666665459e-1f;
  p = p * r + 5.0000001201e-1f;
  p = p * r * r + r + 1.0f;
  const i32x8 exponent = (__builtin_convertvector(n, i32x8) + 127) << 23;
  f32x8 scale;
  std::memcpy(&scale, &exponent, sizeof(scale));
  return p * scale;
}

}  // namespace splat::simd
