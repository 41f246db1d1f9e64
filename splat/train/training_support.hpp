#pragma once
// Small pieces both trainers use: stage timing, the finiteness check behind divergence
// stops, and how often the last good parameters are kept.
#include <chrono>
#include <cmath>
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

// True if every value is finite. A sum is non-finite as soon as one term is (or overflows,
// which is as much a divergence), so one parallel reduction checks a whole group.
inline bool all_finite(std::span<const float> values) {
  const double sum = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, values.size(), 1 << 16), 0.0,
      [&](const tbb::blocked_range<std::size_t>& r, double acc) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) acc += values[i];
        return acc;
      },
      [](double a, double b) { return a + b; });
  return std::isfinite(sum);
}

}  // namespace splat::training
