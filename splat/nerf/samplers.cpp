#include "splat/nerf/samplers.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>

#include "splat/core/error.hpp"
#include "splat/core/random.hpp"

namespace splat {

namespace {

// δᵢ = tᵢ₊₁ − tᵢ, last δ = far − t_last (see stratified_samples).
void deltas_from_positions(std::span<const float> t, float far, std::span<float> delta) {
  const std::size_t n = t.size();
  for (std::size_t i = 0; i + 1 < n; ++i) delta[i] = t[i + 1] - t[i];
  if (n > 0) delta[n - 1] = std::max(0.0f, far - t[n - 1]);
}

void check_same_size(std::size_t a, std::size_t b, const char* what) {
  if (a != b)
    throw ArgumentError(std::string(what) + ": sizes differ (" + std::to_string(a) + " vs " +
                        std::to_string(b) + ")");
}

}  // namespace

void stratified_samples(const RayBounds& bounds, bool jitter, std::mt19937& rng,
                        std::span<float> t, std::span<float> delta) {
  check_same_size(t.size(), delta.size(), "stratified_samples: t and delta");
  const std::size_t n = t.size();
  const float bin = (bounds.far - bounds.near) / float(n);
  for (std::size_t i = 0; i < n; ++i) {
    const float u = jitter ? uniform01(rng) : 0.5f;
    // Rounding can push the last sample a hair past far; clamp so it stays inside.
    t[i] = std::min(bounds.far, bounds.near + (float(i) + u) * bin);
  }
  deltas_from_positions(t, bounds.far, delta);
}

void importance_samples(std::span<const float> t, std::span<const float> delta,
                        std::span<const float> weights, bool jitter, std::mt19937& rng,
                        std::span<float> t_fine) {
  check_same_size(t.size(), delta.size(), "importance_samples: t and delta");
  check_same_size(t.size(), weights.size(), "importance_samples: t and weights");
  const std::size_t n = t.size(), n_fine = t_fine.size();
  if (n_fine == 0) return;
  if (n == 0) throw ArgumentError("importance_samples: no coarse samples to draw from");
  // Masses in double: the running sums below then do not drift across many bins.
  auto mass = [&](std::size_t i) { return double(std::max(weights[i], 0.0f)) + kPdfWeightEpsilon; };
  double total = 0.0;
  for (std::size_t i = 0; i < n; ++i) total += mass(i);
  // Inverse CDF in one pass: the targets u_j·total increase with j, so the interval that
  // holds them only moves forward. `below` is the mass of the intervals before `bin`.
  std::size_t bin = 0;
  double below = 0.0;
  for (std::size_t j = 0; j < n_fine; ++j) {
    const double u = (double(j) + (jitter ? double(uniform01(rng)) : 0.5)) / double(n_fine);
    const double target = u * total;
    while (bin + 1 < n && below + mass(bin) <= target) {
      below += mass(bin);
      ++bin;
    }
    const double fraction = std::clamp((target - below) / mass(bin), 0.0, 1.0);
    t_fine[j] = float(double(t[bin]) + double(delta[bin]) * fraction);
  }
}

void merge_samples(std::span<const float> coarse_t, std::span<const float> coarse_delta,
                   std::span<const float> fine, std::span<float> t, std::span<float> delta) {
  check_same_size(coarse_t.size(), coarse_delta.size(), "merge_samples: coarse t and delta");
  check_same_size(coarse_t.size() + fine.size(), t.size(), "merge_samples: coarse + fine and t");
  check_same_size(t.size(), delta.size(), "merge_samples: t and delta");
  // Two-way merge that remembers where the current coarse interval ends; on a tie the coarse
  // sample comes first, so a fine sample at an interval's start belongs to that interval.
  // Each sample's δ is set once the next position is known.
  const std::size_t n_coarse = coarse_t.size(), n = t.size();
  std::size_t c = 0, f = 0;
  float previous_end = 0.0f;
  for (std::size_t i = 0; i < n; ++i) {
    float end = previous_end;
    if (c < n_coarse && (f == fine.size() || coarse_t[c] <= fine[f])) {
      t[i] = coarse_t[c];
      end = coarse_t[c] + coarse_delta[c];
      // t + (t_next − t) can round one ulp short of t_next: contiguous intervals stay contiguous.
      if (c + 1 < n_coarse && std::nextafter(end, coarse_t[c + 1]) >= coarse_t[c + 1])
        end = std::max(end, coarse_t[c + 1]);
      ++c;
    } else {
      t[i] = fine[f++];
    }
    if (i > 0) delta[i - 1] = std::max(0.0f, std::min(t[i], previous_end) - t[i - 1]);
    previous_end = end;
  }
  if (n > 0) delta[n - 1] = std::max(0.0f, previous_end - t[n - 1]);
}

void hierarchical_samples(std::span<const float> coarse_t, std::span<const float> coarse_delta,
                          std::span<const float> coarse_weights, bool jitter,
                          std::mt19937& rng, std::span<float> fine_scratch, std::span<float> t,
                          std::span<float> delta) {
  importance_samples(coarse_t, coarse_delta, coarse_weights, jitter, rng, fine_scratch);
  merge_samples(coarse_t, coarse_delta, fine_scratch, t, delta);
}

}  // namespace splat
