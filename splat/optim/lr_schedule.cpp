#include "splat/optim/lr_schedule.hpp"

#include <algorithm>
#include <cmath>

namespace splat {

double ExponentialLrSchedule::operator()(int step) const {
  // As the official helper: a negative step or an all-zero schedule means "no learning".
  if (step < 0 || (lr_init == 0.0 && lr_final == 0.0)) return 0.0;
  return at_fraction(double(step) / double(max_steps));
}

double ExponentialLrSchedule::at_fraction(double t) const {
  if (lr_init == 0.0 && lr_final == 0.0) return 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return std::exp(std::log(lr_init) * (1.0 - t) + std::log(lr_final) * t);
}

}  // namespace splat
