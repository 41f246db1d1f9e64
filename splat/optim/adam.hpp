#pragma once
// Adam over the Gaussian parameters, one learning rate per parameter group, with PyTorch's
// semantics as the official 3DGS trainer uses them (β1 0.9, β2 0.999, ε 1e-15, one step count
// shared by all Gaussians, every Gaussian updated every step even when its gradient is zero).
// The moments are stored as GaussianModel-shaped arrays so clone, split and prune apply the
// same row operations to parameters and optimiser state alike.
//
// Per element, with t the step count after incrementing, in float as PyTorch does on the
// GPU (the bias corrections in double, as Python computes them):
//   m ← m + (1 − β1)(g − m)            (= β1·m + (1 − β1)·g; PyTorch ≥ 2 writes it as a lerp)
//   v ← β2·v + (1 − β2)·g·g
//   p ← p − lr/(1 − β1ᵗ) · m / (sqrt(v)/sqrt(1 − β2ᵗ) + ε)
// and, while a parameter average is kept, with s the step just added to p:
//   d ← β_avg·(d − s)                 (d = average − p: the average moves to β_avg·a + (1 − β_avg)·p)
#include <optional>
#include <vector>

#include "splat/gaussians/gaussian_model.hpp"
#include "splat/gaussians/sh_gradient_factors.hpp"

namespace splat {

// Double, as PyTorch takes them from Python: 1 − β and the bias corrections are formed in
// double and only then rounded to float (1 − 0.999f in float would be off by 1.3e-5).
struct AdamSettings {
  double beta1 = 0.9, beta2 = 0.999, epsilon = 1e-15;
  // While the state keeps a parameter average (AdamState::averaging()), each step moves it
  // (1 − average_decay) of the way to the stepped parameters: an exponential moving average
  // of the iterates over about the last 1/(1 − average_decay) steps.
  double average_decay = 0.99;
};

// Learning rates for one step, per parameter group.
struct GroupLearningRates {
  float means = 1.6e-4f;      // already scaled by the scene extent and decayed (lr_schedule.hpp)
  float sh_dc = 2.5e-3f;      // SH band 0 (k = 0)
  float sh_rest = 2.5e-3f / 20.0f;  // SH bands 1..3
  float opacity = 0.05f;
  float scales = 5e-3f;
  float rotations = 1e-3f;

  // Every rate times `factor`.
  void multiply(float factor) {
    for (float* rate : {&means, &sh_dc, &sh_rest, &opacity, &scales, &rotations}) *rate *= factor;
  }
};

// Which groups a step touches. PyTorch skips a parameter without a gradient, moments and all;
// the official trainer hits that when a tensor was just replaced: every group after
// densification (the caller skips the whole step then) and only the opacity group after an
// opacity reset without densification (white background at densify_from_iter). A skipped
// group's elements keep their parameters and moments.
struct AdamGroupMask {
  bool means = true, sh_dc = true, sh_rest = true, opacity = true, scales = true,
       rotations = true;
  // SH bands above this degree are not stepped: the trainer passes its active degree, whose
  // higher bands have had no gradient yet, so their moments are zero and a step would leave
  // parameters and moments exactly as they are (m and v stay 0, p moves by −lr·0/ε = −0).
  // Early in a run that is most of each row. The caller must keep that promise.
  int sh_degree = kMaxShDegree;
};

struct AdamState {
  GaussianModel first_moment;   // m, same shape as the model
  GaussianModel second_moment;  // v
  // The parameter average (Polyak averaging; AdamSettings::average_decay) as its offset from
  // the parameters, average − parameters, while averaging(). An offset rather than the average
  // itself, so that the row operations that give a new or moved Gaussian zero moments also
  // start its average at its parameters.
  GaussianModel average_offset;
  // The caller's iteration the average started at (its first step follows it); none while
  // no average is kept. The caller reports it and its checkpoint keeps it.
  std::optional<int> average_start;
  // Steps taken (bias correction), shared by every group. PyTorch keeps one count per group;
  // they differ only when a group is skipped (AdamGroupMask), which the official trainer does
  // at most once, at iteration 500, where 0.9⁵⁰⁰ makes the difference vanish in float.
  int step = 0;

  // Zero moments shaped like `model` (step count kept), and no average.
  void reset_like(const GaussianModel& model);
  // Starts the parameter average at `model`'s parameters (a zero offset of its shape), at
  // the caller's `iteration`.
  void start_average(const GaussianModel& model, int iteration);
  bool averaging() const { return average_start.has_value(); }
  // The average's parameters: `params` plus the offset (`params` itself without an average).
  GaussianModel averaged(const GaussianModel& params) const;
  // The rows density control must keep aligned with the model's: the moments, and the
  // average's offset while there is one.
  std::vector<GaussianModel*> rows();
};

// One Adam step: increments state.step, then updates every element of the active groups.
// `grads` and both moments must have the model's shape (reset_like creates the moments);
// otherwise ArgumentError. Parallel over Gaussians in fixed-size chunks; every element is
// computed independently with the same instructions, so the result is bit-identical for any
// thread count.
// With `sh_factors`, the SH group's gradient is theirs (sh_gradient_factors.hpp: each row
// formed as it is stepped, the same floats as the full rows) and grads.sh is not read.
void adam_step(GaussianModel& params, const GaussianModel& grads, AdamState& state,
               const GroupLearningRates& lr, const AdamSettings& settings = {},
               const AdamGroupMask& active = {}, const ShGradientFactors* sh_factors = nullptr);

}  // namespace splat
