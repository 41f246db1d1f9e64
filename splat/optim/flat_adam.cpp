#include "splat/optim/flat_adam.hpp"

#include <cmath>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "splat/core/error.hpp"

namespace splat {

void FlatAdam::step(std::span<float> params, std::span<const float> grad, float learning_rate) {
  if (params.size() != m_.size() || grad.size() != m_.size())
    throw ArgumentError("FlatAdam::step: " + std::to_string(params.size()) + " parameters and " +
                        std::to_string(grad.size()) + " gradients for an optimiser of " +
                        std::to_string(m_.size()));
  ++step_count_;
  // Bias corrections in double, as Python forms them, then rounded once.
  const double t = double(step_count_);
  const float step_size = float(learning_rate / (1.0 - std::pow(settings_.beta1, t)));
  const float inv_sqrt_correction2 = float(1.0 / std::sqrt(1.0 - std::pow(settings_.beta2, t)));
  const float beta1 = float(settings_.beta1), one_minus_beta1 = float(1.0 - settings_.beta1);
  const float beta2 = float(settings_.beta2), one_minus_beta2 = float(1.0 - settings_.beta2);
  const float epsilon = float(settings_.epsilon);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, params.size(), 1 << 14), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const float g = grad[i];
      m_[i] = beta1 * m_[i] + one_minus_beta1 * g;
      v_[i] = beta2 * v_[i] + one_minus_beta2 * g * g;
      params[i] -= step_size * m_[i] / (std::sqrt(v_[i]) * inv_sqrt_correction2 + epsilon);
    }
  });
}

}  // namespace splat
