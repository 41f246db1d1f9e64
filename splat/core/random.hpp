#pragma once
// Portable random numbers from std::mt19937. The standard distributions are
// implementation-defined (libstdc++ and libc++ give different sequences), so a seed would
// not reproduce a model across platforms; these are written out instead.
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>

namespace splat {

// SplitMix64's finaliser: a 64-bit value mixed so that every input bit moves every output bit
// (counter-based random streams, fingerprints).
inline std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// Uniform in [0, 1): the top 24 bits of one draw, so every value is exact in float and 1 is
// never returned.
inline float uniform01(std::mt19937& rng) {
  constexpr float kTwoToMinus24 = 1.0f / 16777216.0f;
  return float(rng() >> 8) * kTwoToMinus24;
}

// Standard normal samples by the Box–Muller transform: two uniforms give two independent
// normals. Fills `out[0..count)` in order, using exactly 2·ceil(count/2) draws.
inline void fill_standard_normal(std::mt19937& rng, float* out, std::size_t count) {
  for (std::size_t i = 0; i < count; i += 2) {
    // 1 − u lies in (0, 1], so the logarithm is finite.
    const double radius = std::sqrt(-2.0 * std::log(1.0 - double(uniform01(rng))));
    const double angle = 2.0 * std::numbers::pi * double(uniform01(rng));
    out[i] = float(radius * std::cos(angle));
    if (i + 1 < count) out[i + 1] = float(radius * std::sin(angle));
  }
}

}  // namespace splat
