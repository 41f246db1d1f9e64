#pragma once
// The learning-rate schedule of the official trainer, which both trainers use: the splats'
// position rate (its end points are settings, training_config.hpp), their appearance and pose
// decays, and the NeRF's rate.
namespace splat {

// The official get_expon_lr_func without the delay phase (lr_delay_steps 0, its setting for
// every group it schedules): a log-linear decay from lr_init to lr_final over max_steps
// steps, constant at lr_final after that and 0 for negative steps.
//   t = clamp(step / max_steps, 0, 1);  lr = exp((1 − t)·ln(lr_init) + t·ln(lr_final))
struct ExponentialLrSchedule {
  double lr_init = 0;
  double lr_final = 0;
  int max_steps = 1;

  double operator()(int step) const;
  // The rate at fraction t of the schedule (clamped to [0, 1]): operator()(step) is
  // at_fraction(step / max_steps) for steps ≥ 0.
  double at_fraction(double t) const;
};

}  // namespace splat
