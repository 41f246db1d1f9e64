#pragma once
// Small pieces both trainers use: stage timing, the finiteness check behind divergence
// stops, and how often the last good parameters are kept.
#include <bit>
#include <chrono>
#include <cstdint>
#include <span>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

namespace splat::training {

using Clock = std::chrono::steady_clock;

inline double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Keeps the parameters this often (iterations) once they are checked finite, so a diverged
// run can still hand back a good model.
constexpr int kLastGoodInterval = 100;

// True if every value is finite: no value has the all-ones exponent of ±∞ and NaN. An OR of
// bit tests, which the compiler vectorises (a running sum was one dependent addition per
// value, about 1 % of a training iteration).
inline bool all_finite(std::span<const float> values) {
  constexpr std::uint32_t kExponent = 0x7f800000u;
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, values.size(), 1 << 16), true,
      [&](const tbb::blocked_range<std::size_t>& r, bool finite) {
        std::uint32_t non_finite = 0;
        for (std::size_t i = r.begin(); i != r.end(); ++i)
          non_finite |= std::uint32_t((std::bit_cast<std::uint32_t>(values[i]) & kExponent) == kExponent);
        return finite && non_finite == 0;
      },
      [](bool a, bool b) { return a && b; });
}

}  // namespace splat::training
