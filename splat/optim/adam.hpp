#pragma once
// Adam over the Gaussian parameters, one learning rate per parameter group, with PyTorch's
// semantics as the official 3DGS trainer uses them (β1 0.9, β2 0.999, ε 1e-15, one step count
// shared by all Gaussians, every Gaussian updated every step even when its gradient is zero).
// The moments are stored as GaussianModel-shaped arrays so clone, split and prune apply the
// same row operations to parameters and optimiser state alike.
#include "splat/gaussians/gaussian_model.hpp"

namespace splat {

struct AdamSettings {
  float beta1 = 0.9f, beta2 = 0.999f, epsilon = 1e-15f;
};

// Learning rates for one step, per parameter group.
struct GroupLearningRates {
  float means = 1.6e-4f;      // already scaled by the scene extent and decayed (lr_schedule.hpp)
  float sh_dc = 2.5e-3f;      // SH band 0 (k = 0)
  float sh_rest = 2.5e-3f / 20.0f;  // SH bands 1..3
  float opacity = 0.05f;
  float scales = 5e-3f;
  float rotations = 1e-3f;
};

struct AdamState {
  GaussianModel first_moment;   // m, same shape as the model
  GaussianModel second_moment;  // v
  int step = 0;                 // steps taken (bias correction)

  // Zero moments shaped like `model` (step count kept).
  void reset_like(const GaussianModel& model);
};

// One Adam step: params −= lr · m̂ / (sqrt(v̂) + ε). `grads` has the model's shape. Parallel
// over Gaussians; the result does not depend on the thread count.
void adam_step(GaussianModel& params, const GaussianModel& grads, AdamState& state,
               const GroupLearningRates& lr, const AdamSettings& settings = {});

}  // namespace splat
