#pragma once
// Moving Gaussians without changing the image (3DGS as MCMC, Kheradmand et al. 2024): when
// one Gaussian is replaced by `copies` identical ones at its place, each copy gets
//   o' = 1 − (1 − o)^(1/copies)     (the copies together block as much light at the centre)
//   s' = s · o / Σ_{i=1..copies} Σ_{k=0..i−1} C(i−1, k) (−1)^k (o')^(k+1) / sqrt(k+1)
// (the scale that keeps the composited footprint's integral). Dead Gaussians relocated onto
// live ones and new Gaussians added beside live ones both go through this, so neither step
// disturbs what the model already renders.
#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

#include "splat/optim/density_control.hpp"

namespace splat {

// The most copies one Gaussian may be split into in one step (the alternating sum above
// loses precision beyond this).
constexpr int kMaxRelocationCopies = 51;

struct RelocatedShape {
  float opacity;      // o'
  float scale_ratio;  // s' / s
};

// o' and s'/s for `copies` (1..kMaxRelocationCopies) copies of a Gaussian of opacity
// `opacity`; o' is kept within [min_opacity, 1 − 1e-6].
RelocatedShape relocated_shape(float opacity, int copies, float min_opacity);

// `count` source rows drawn with replacement, each with probability ∝ its opacity among the
// rows whose flag in `eligible` is set (all rows if `eligible` is empty), from `rng`.
// Returns the sources in draw order; empty if no row is eligible or all have zero opacity.
std::vector<std::size_t> sample_by_opacity(const GaussianModel& model,
                                           const std::vector<std::uint8_t>& eligible,
                                           std::size_t count, std::mt19937& rng);

// Each row of `targets` becomes a copy of the row in `sources` at the same position, and
// every source and its copies take the relocated opacity and scale for (copies + 1).
// The Adam moments of sources and targets are zeroed, their statistics copied from the
// source. Returns the number of rows moved.
std::size_t relocate_rows(AlignedRows& rows, const std::vector<std::size_t>& targets,
                          const std::vector<std::size_t>& sources, float min_opacity);

// Appends one copy per entry of `sources` (repeats allowed) at its source's place, with the
// relocated opacity and scale applied to sources and copies alike; the sources' Adam
// moments are zeroed, the copies start at zero. Returns the number of rows added.
std::size_t add_relocated_copies(AlignedRows& rows, const std::vector<std::size_t>& sources,
                                 float min_opacity);

}  // namespace splat
