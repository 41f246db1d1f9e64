#pragma once
// Where along a ray the NeRF evaluates its field: stratified samples (the coarse pass) and
// hierarchical importance samples drawn from the coarse pass's weights (the fine pass),
// after Mildenhall et al. 2020, section 5.2.
//
// A sample is a position tᵢ and a length δᵢ: its density σᵢ is taken as constant over
// [tᵢ, tᵢ + δᵢ], which is what αᵢ = 1 − exp(−σᵢ δᵢ) integrates. Within one ray the samples
// are sorted and their intervals do not overlap.
//
// No gradient flows through the sample positions (as in the paper): t and δ are constants
// of the volume-rendering step, and the fine samples depend on the coarse weights only
// through this non-differentiable sampling.
#include <random>
#include <span>

#include "splat/core/rays.hpp"

namespace splat {

// Added to every coarse weight before it becomes a PDF (the paper's 1e-5): keeps the PDF
// defined on rays whose weights are all zero, where it falls back to uniform.
constexpr float kPdfWeightEpsilon = 1e-5f;

// n = t.size() stratified samples in [near, far]: the interval is cut into n equal bins and
// sample i is at near + (i + uᵢ)·(far − near)/n, with uᵢ drawn uniformly in [0, 1) from
// `rng` in bin order when `jitter`, else uᵢ = 0.5 (bin midpoints, for evaluation: `rng` is
// then not used). The t are non-decreasing and within [near, far].
// δᵢ = tᵢ₊₁ − tᵢ and the last δ = far − t_last (not the paper's 1e10): the samples then
// cover [t₀, far] exactly once, the last one's α stays finite for finite σ (with δ = 1e10 any
// σ > 0 makes α = 1, and the compositor's transmittance floor would refuse to blend it at
// all), and the intervals are the bins the hierarchical sampler draws from.
// Throws ArgumentError if t and delta differ in size.
void stratified_samples(const RayBounds& bounds, bool jitter, std::mt19937& rng,
                        std::span<float> t, std::span<float> delta);

// Draws n_fine = t_fine.size() positions by inverse transform sampling of the piecewise-
// constant PDF over the intervals [tᵢ, tᵢ + δᵢ] with mass ∝ max(wᵢ, 0) + kPdfWeightEpsilon
// (wᵢ = Tᵢ αᵢ, the coarse pass's weights). The uniforms are stratified, u_j = (j + U_j)/n_fine
// with U_j from `rng` when `jitter`, else the midpoints u_j = (j + 0.5)/n_fine (deterministic,
// for evaluation). u is increasing, so t_fine comes out sorted. One pass, no allocation.
// Throws ArgumentError if t, delta and weights differ in size, or t is empty while n_fine > 0.
void importance_samples(std::span<const float> t, std::span<const float> delta,
                        std::span<const float> weights, bool jitter, std::mt19937& rng,
                        std::span<float> t_fine);

// Merges the coarse samples (positions and lengths) with sorted fine positions drawn inside
// the coarse intervals (importance_samples) into `t` and `delta` (size coarse + fine). Each
// merged sample's interval runs to the next sample but never past the end of the coarse
// interval that holds it: where the coarse intervals leave gaps (samples dropped in empty
// cells), no sample's density is stretched across a gap. Without gaps this is
// δᵢ = tᵢ₊₁ − tᵢ and the last δ = the coarse end (far). Throws ArgumentError on mismatched sizes.
void merge_samples(std::span<const float> coarse_t, std::span<const float> coarse_delta,
                   std::span<const float> fine, std::span<float> t, std::span<float> delta);

// The fine pass of one ray in one call: importance_samples into `fine_scratch` (its size is
// n_fine), then merge_samples with the coarse samples into t and delta (size n_coarse +
// n_fine).
void hierarchical_samples(std::span<const float> coarse_t, std::span<const float> coarse_delta,
                          std::span<const float> coarse_weights, bool jitter,
                          std::mt19937& rng, std::span<float> fine_scratch, std::span<float> t,
                          std::span<float> delta);

}  // namespace splat
