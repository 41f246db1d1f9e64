#pragma once
// Float and mask vectors of kLanes = 8 lanes (GCC/Clang vector extensions): one AVX
// register, half a 16-pixel tile row. The compiler lowers them to whatever the target has
// (pairs of SSE registers at worst), so the code stays portable while the hot loops run one
// instruction per kLanes pixels. Eight, not sixteen, even where the CPU has AVX-512: most
// splats are a few pixels wide, and 8-pixel chunks evaluate 36 % fewer pixels than whole
// 16-pixel rows (conformance model at 800×800: 7.7 against 12.2 million per frame), for an
// 18 % faster blend on the AMD EPYC this project measures on. On an Intel Xeon with full-width
// AVX-512 a 16-lane step costs about 1.2 times an 8-lane one, and whole rows take 0.75–0.78
// times the chunk steps, so there too the gain would be nil (bench/HISTORY.md, issue 39,
// nineteenth session). On an AMD family 26 CPU (twentieth session) a 16-lane step costs only
// 1.05 times an 8-lane one, so there the forward blend walks whole 16-lane rows
// (blend.cpp, BlendWalk). The blend's backward also takes whole 16-lane rows (f32x16 below)
// where a splat blended in both chunks of a row.
//
// The helpers below have scalar overloads too, so templated code (the shared compositor)
// runs unchanged on `float` + `bool` (one ray) or `f32v` + `i32v` (kLanes pixels).
#include <cstdint>
#include <cstring>
#if defined(__AVX__)
#include <immintrin.h>
#endif

namespace splat::simd {

constexpr int kLanes = 8;
using f32v = float __attribute__((vector_size(4 * kLanes)));
using i32v = std::int32_t __attribute__((vector_size(4 * kLanes)));  // lanes are 0 or -1
using f64v = double __attribute__((vector_size(8 * kLanes)));

// Lane-wise choice: where `mask` is set take `a`, else `b`.
inline f32v select(i32v mask, f32v a, f32v b) { return mask ? a : b; }
inline i32v select(i32v mask, i32v a, i32v b) { return mask ? a : b; }
inline float select(bool mask, float a, float b) { return mask ? a : b; }
inline double select(bool mask, double a, double b) { return mask ? a : b; }

inline i32v mask_and(i32v a, i32v b) { return a & b; }
inline i32v mask_and_not(i32v a, i32v b) { return a & ~b; }  // a and not b
inline i32v mask_or(i32v a, i32v b) { return a | b; }
inline bool mask_and(bool a, bool b) { return a && b; }
inline bool mask_and_not(bool a, bool b) { return a && !b; }
inline bool mask_or(bool a, bool b) { return a || b; }

inline bool any(i32v mask) {
#if defined(__AVX512VL__)
  const __m256i m = reinterpret_cast<__m256i>(mask);
  return _mm256_test_epi32_mask(m, m) != 0;  // one mask-register test
#elif defined(__AVX__)
  const __m256i m = reinterpret_cast<__m256i>(mask);
  return !_mm256_testz_si256(m, m);
#else
  std::uint64_t words[kLanes / 2];
  std::memcpy(words, &mask, sizeof(mask));
  std::uint64_t bits = 0;
  for (std::uint64_t w : words) bits |= w;
  return bits != 0;
#endif
}
inline bool any(bool mask) { return mask; }

// One bit per lane (bit i for lane i), set where the lane is.
inline std::uint32_t bits(i32v mask) {
#if defined(__AVX__)
  return std::uint32_t(_mm256_movemask_ps(reinterpret_cast<__m256>(mask)));
#else
  std::uint32_t b = 0;
  for (int i = 0; i < kLanes; ++i) b |= std::uint32_t(mask[i] != 0) << i;
  return b;
#endif
}

inline int count(i32v mask) {
  int n = 0;
  for (int i = 0; i < kLanes; ++i) n += mask[i] != 0;
  return n;
}

// Sum of the lanes, always in the same order (deterministic).
inline float reduce_add(f32v v) {
  float sum = 0.0f;
  for (int i = 0; i < kLanes; ++i) sum += v[i];
  return sum;
}

inline int reduce_max(i32v v) {
  int m = v[0];
  for (int i = 1; i < kLanes; ++i) m = v[i] > m ? v[i] : m;
  return m;
}

inline f32v broadcast(float x) { return f32v{} + x; }
// a < b ? a : b and a > b ? a : b, lane-wise. x86's min and max compute exactly these (the
// second operand when either is NaN or both are zeros), in one instruction where the compiler
// would otherwise emit a compare and a blend (it may not assume finite, unsigned-zero math).
inline f32v min(f32v a, f32v b) {
#if defined(__AVX__)
  return reinterpret_cast<f32v>(_mm256_min_ps(reinterpret_cast<__m256>(a), reinterpret_cast<__m256>(b)));
#else
  return a < b ? a : b;
#endif
}
inline f32v max(f32v a, f32v b) {
#if defined(__AVX__)
  return reinterpret_cast<f32v>(_mm256_max_ps(reinterpret_cast<__m256>(a), reinterpret_cast<__m256>(b)));
#else
  return a > b ? a : b;
#endif
}

// A scalar function applied to every lane, one lane at a time (for what has no instruction:
// libm's exp and log, which the vector code must match bit for bit).
inline f32v per_lane(f32v x, float (*f)(float)) {
  for (int i = 0; i < kLanes; ++i) x[i] = f(x[i]);
  return x;
}

// Lane-wise sqrt, floor, ceil and fused a·b + c: exactly what std::sqrt, std::floor,
// std::ceil and std::fma give each lane (IEEE operations, correctly rounded).
#if defined(__AVX__)
inline f32v sqrt(f32v x) { return reinterpret_cast<f32v>(_mm256_sqrt_ps(reinterpret_cast<__m256>(x))); }
inline f32v floor(f32v x) { return reinterpret_cast<f32v>(_mm256_floor_ps(reinterpret_cast<__m256>(x))); }
inline f32v ceil(f32v x) { return reinterpret_cast<f32v>(_mm256_ceil_ps(reinterpret_cast<__m256>(x))); }
#else
inline f32v sqrt(f32v x) { return per_lane(x, [](float v) { return __builtin_sqrtf(v); }); }
inline f32v floor(f32v x) { return per_lane(x, [](float v) { return __builtin_floorf(v); }); }
inline f32v ceil(f32v x) { return per_lane(x, [](float v) { return __builtin_ceilf(v); }); }
#endif
inline f32v fma(f32v a, f32v b, f32v c) {
#if defined(__FMA__)
  return reinterpret_cast<f32v>(_mm256_fmadd_ps(reinterpret_cast<__m256>(a), reinterpret_cast<__m256>(b),
                                                reinterpret_cast<__m256>(c)));
#else
  for (int i = 0; i < kLanes; ++i) a[i] = __builtin_fmaf(a[i], b[i], c[i]);
  return a;
#endif
}
inline f32v abs(f32v x) {  // the sign bit cleared, as std::abs
  i32v bits;
  std::memcpy(&bits, &x, sizeof(x));
  bits &= 0x7fffffff;
  std::memcpy(&x, &bits, sizeof(x));
  return x;
}

// rows[i][j] becomes rows[j][i] (an 8 × 8 transpose in three rounds of two-vector shuffles).
inline void transpose(f32v rows[kLanes]) {
  static_assert(kLanes == 8, "an 8 x 8 transpose");
  f32v t[8], u[8];
  for (int i = 0; i < 8; i += 2) {
    t[i] = __builtin_shufflevector(rows[i], rows[i + 1], 0, 8, 1, 9, 4, 12, 5, 13);
    t[i + 1] = __builtin_shufflevector(rows[i], rows[i + 1], 2, 10, 3, 11, 6, 14, 7, 15);
  }
  for (int i = 0; i < 8; i += 4)
    for (int h = 0; h < 2; ++h) {
      u[i + 2 * h] = __builtin_shufflevector(t[i + h], t[i + h + 2], 0, 1, 8, 9, 4, 5, 12, 13);
      u[i + 2 * h + 1] = __builtin_shufflevector(t[i + h], t[i + h + 2], 2, 3, 10, 11, 6, 7, 14, 15);
    }
  for (int j = 0; j < 4; ++j) {
    rows[j] = __builtin_shufflevector(u[j], u[j + 4], 0, 1, 2, 3, 8, 9, 10, 11);
    rows[j + 4] = __builtin_shufflevector(u[j], u[j + 4], 4, 5, 6, 7, 12, 13, 14, 15);
  }
}

// Rows of `width` floats, one row per lane, as one vector per column: columns[j][l] =
// rows[l][j]. Reads only rows[l][0 .. width), kLanes floats at a time and transposed.
inline void load_columns(const float* const rows[kLanes], int width, f32v* columns) {
  int j = 0;
  for (; j + kLanes <= width; j += kLanes) {
    f32v block[kLanes];
    for (int l = 0; l < kLanes; ++l) std::memcpy(&block[l], rows[l] + j, sizeof(f32v));
    transpose(block);
    for (int k = 0; k < kLanes; ++k) columns[j + k] = block[k];
  }
  for (; j < width; ++j)
    for (int l = 0; l < kLanes; ++l) columns[j][l] = rows[l][j];
}

// The reverse for the lanes whose bit is set in `lanes`: rows[l][j] = columns[j][l] for
// j < width. The other lanes' rows are not touched (nor read).
inline void store_columns(const f32v* columns, int width, std::uint32_t lanes, float* const rows[kLanes]) {
  int j = 0;
  for (; j + kLanes <= width; j += kLanes) {
    f32v block[kLanes];
    for (int k = 0; k < kLanes; ++k) block[k] = columns[j + k];
    transpose(block);
    for (std::uint32_t todo = lanes; todo != 0; todo &= todo - 1) {
      const int l = __builtin_ctz(todo);
      std::memcpy(rows[l] + j, &block[l], sizeof(f32v));
    }
  }
  for (; j < width; ++j)
    for (std::uint32_t todo = lanes; todo != 0; todo &= todo - 1) {
      const int l = __builtin_ctz(todo);
      rows[l][j] = columns[j][l];
    }
}

// reduce_add of kLanes vectors at once: lane i of the result is reduce_add(v[i]), summed in
// the same order (so bit for bit the same), by a transpose and kLanes − 1 vector additions.
inline f32v reduce_add_each(const f32v v[kLanes]) {
  f32v t[kLanes];
  for (int i = 0; i < kLanes; ++i) t[i] = v[i];
  transpose(t);
  f32v sum = t[0];
  for (int i = 1; i < kLanes; ++i) sum += t[i];
  return sum;
}

// ---- Whole tile rows: 16 lanes --------------------------------------------------------
// The blend's backward takes the rows a splat covers whole (both 8-pixel chunks) as one
// 16-lane vector: one AVX-512 register, half the instructions per pixel of two 8-lane ones.
constexpr int kRowLanes = 16;
using f32x16 = float __attribute__((vector_size(4 * kRowLanes)));
using i32x16 = std::int32_t __attribute__((vector_size(4 * kRowLanes)));

inline f32x16 concat(f32v low, f32v high) {
  return __builtin_shufflevector(low, high, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
}
inline i32x16 concat(i32v low, i32v high) {
  return __builtin_shufflevector(low, high, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
}
inline f32v low_half(f32x16 v) { return __builtin_shufflevector(v, v, 0, 1, 2, 3, 4, 5, 6, 7); }
inline f32v high_half(f32x16 v) { return __builtin_shufflevector(v, v, 8, 9, 10, 11, 12, 13, 14, 15); }
inline i32v low_half(i32x16 v) { return __builtin_shufflevector(v, v, 0, 1, 2, 3, 4, 5, 6, 7); }
inline i32v high_half(i32x16 v) { return __builtin_shufflevector(v, v, 8, 9, 10, 11, 12, 13, 14, 15); }

inline f32x16 select(i32x16 mask, f32x16 a, f32x16 b) { return mask ? a : b; }
inline i32x16 select(i32x16 mask, i32x16 a, i32x16 b) { return mask ? a : b; }
inline i32x16 mask_and(i32x16 a, i32x16 b) { return a & b; }
inline i32x16 mask_and_not(i32x16 a, i32x16 b) { return a & ~b; }
inline i32x16 mask_or(i32x16 a, i32x16 b) { return a | b; }
inline bool any(i32x16 mask) {
#if defined(__AVX512F__)
  const __m512i m = reinterpret_cast<__m512i>(mask);
  return _mm512_test_epi32_mask(m, m) != 0;
#else
  return any(__builtin_shufflevector(mask, mask, 0, 1, 2, 3, 4, 5, 6, 7) |
             __builtin_shufflevector(mask, mask, 8, 9, 10, 11, 12, 13, 14, 15));
#endif
}
inline int count(i32x16 mask) { return count(low_half(mask)) + count(high_half(mask)); }
// As the 8-lane min and max: the second operand when either is NaN.
inline f32x16 min(f32x16 a, f32x16 b) {
#if defined(__AVX512F__)
  return reinterpret_cast<f32x16>(_mm512_maskz_min_ps(0xffff, reinterpret_cast<__m512>(a), reinterpret_cast<__m512>(b)));
#else
  return a < b ? a : b;
#endif
}
inline f32x16 max(f32x16 a, f32x16 b) {
#if defined(__AVX512F__)
  return reinterpret_cast<f32x16>(_mm512_maskz_max_ps(0xffff, reinterpret_cast<__m512>(a), reinterpret_cast<__m512>(b)));
#else
  return a > b ? a : b;
#endif
}

namespace detail {
// (The 512-bit intrinsics are the zero-masked forms with every lane set: GCC 12 warns that
// the unmasked ones read an uninitialised register.)
// round(x) to the nearest integer and p · 2ⁿ, for exp2_nonpositive: one instruction each
// where AVX-512 has them, else the same arithmetic in the other widths' terms (an 8-lane and
// a 16-lane call give every lane the same result, which the backward's rows rely on).
#if defined(__AVX512VL__)
inline f32v round_nearest(f32v x) {
  return reinterpret_cast<f32v>(
      _mm256_roundscale_ps(reinterpret_cast<__m256>(x), _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC));
}
inline f32x16 round_nearest(f32x16 x) {
  return reinterpret_cast<f32x16>(
      _mm512_maskz_roundscale_ps(0xffff, reinterpret_cast<__m512>(x), _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC));
}
inline f32v scale_by_power_of_two(f32v p, f32v n) {
  return reinterpret_cast<f32v>(_mm256_scalef_ps(reinterpret_cast<__m256>(p), reinterpret_cast<__m256>(n)));
}
inline f32x16 scale_by_power_of_two(f32x16 p, f32x16 n) {
  return reinterpret_cast<f32x16>(_mm512_maskz_scalef_ps(0xffff, reinterpret_cast<__m512>(p), reinterpret_cast<__m512>(n)));
}
#else
// round(x) as the truncation of x − ½ (x <= 0): f lands in (−½, ½].
template <class F>
F round_nearest(F x) {
  using I = decltype(x < x);
  return __builtin_convertvector(__builtin_convertvector(x - 0.5f, I), F);
}
// 2ⁿ built in the exponent bits (n >= −126), then one multiplication.
template <class F>
F scale_by_power_of_two(F p, F n) {
  using I = decltype(p < p);
  const I exponent = (__builtin_convertvector(n, I) + 127) << 23;
  F scale;
  std::memcpy(&scale, &exponent, sizeof(scale));
  return p * scale;
}
#endif
}  // namespace detail

// Where exp2_nonpositive stops: below it every lane gets 2^kExp2Floor. An α there is at most
// 2^−64, far below the 1/255 that draws, so no image or gradient can tell; a floor at the
// float range's end (−126) gave subnormal numbers (the polynomial, below 1, times 2^−126, and
// α = o·that), which some cores take a slow path for: on the AMD family 26 EPYC the forward
// blend of the conformance frame at 800² in 8-pixel chunks took 11.5 ms at one thread with
// −126 and 11.1 with −64, in whole 16-pixel rows (more far-off lanes) 9.0 against 5.2 ms at
// two threads (bench/HISTORY.md, issue 39, 21st session).
constexpr float kExp2Floor = -64.0f;

// 2^x for kExp2Floor <= x <= 0 (2^kExp2Floor below), lane-wise on 8 or 16 lanes. The rasterizer's
// α is o·2^(power·log2 e): log2 e is folded into the exponent's coefficients once per splat,
// so the range reduction is exact (x = n + f, n = round(x), f = x − n in [−½, ½] without
// rounding) and one step shorter than e^x's (which must round x·log2 e, then subtract n·ln 2).
// The blend waits on this chain at every pixel-Gaussian pair, so it is kept short: a
// degree-6 minimax polynomial for 2^f by Estrin's scheme (three dependent steps after f),
// times 2^n. Relative error below 1.71e-7, 1.5 ulp (measured against double exp2 at every
// float from 0 to −126 before the floor was raised to kExp2Floor). Deterministic on every machine (no libm call), which keeps renders
// identical across platforms and thread counts.
template <class F>
F exp2_nonpositive(F x) {
  x = max(x, F{} + kExp2Floor);
  const F n = detail::round_nearest(x);
  const F f = x - n;
  // 2^f ≈ (c0 + c1 f) + f²(c2 + c3 f) + f⁴(c4 + c5 f + c6 f²).
  const F f2 = f * f;
  const F low = f * 6.9314720574e-1f + 1.0000000006f;
  const F mid = f * 5.5503287770e-2f + 2.4022646891e-1f;
  const F high = f * 1.3399931203e-3f + 9.6184889525e-3f;
  const F f4 = f2 * f2;
  const F p = (f2 * 1.5345813165e-4f + high) * f4 + (mid * f2 + low);
  return detail::scale_by_power_of_two(p, n);
}

}  // namespace splat::simd
