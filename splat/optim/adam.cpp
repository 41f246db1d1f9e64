#include "splat/optim/adam.hpp"

#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include <cmath>
#include <string>

#include "splat/core/error.hpp"

namespace splat {
namespace {

// Gaussians per task. The partitioner splits the range by halving down to this size
// whatever the thread count, so chunk boundaries (and with them any remainder loops) do not
// depend on it; 2048 Gaussians × 59 floats × 4 arrays is about 2 MB, a few per core's cache.
constexpr std::size_t kGaussiansPerTask = 2048;

// Scalars shared by every element of a step.
struct StepCoefficients {
  float one_minus_beta1;
  float beta2;
  float one_minus_beta2;
  float bias_correction2_sqrt;  // sqrt(1 − β2ᵗ)
  float epsilon;
};

// The Adam update of `count` consecutive elements with one step size (lr / (1 − β1ᵗ)).
// Written as a plain loop over restrict pointers so the compiler vectorises it; the
// arithmetic follows PyTorch's order term by term (see adam.hpp).
inline void update_elements(float* __restrict param, const float* __restrict grad,
                            float* __restrict m, float* __restrict v, std::size_t count,
                            float step_size, const StepCoefficients& c) {
  for (std::size_t i = 0; i < count; ++i) {
    const float g = grad[i];
    const float m_new = m[i] + c.one_minus_beta1 * (g - m[i]);
    const float v_new = v[i] * c.beta2 + c.one_minus_beta2 * g * g;
    m[i] = m_new;
    v[i] = v_new;
    const float denom = std::sqrt(v_new) / c.bias_correction2_sqrt + c.epsilon;
    param[i] = param[i] + (-step_size) * (m_new / denom);
  }
}

// Views of one parameter array across the four models, with its row width.
struct ArrayViews {
  float* param;
  const float* grad;
  float* m;
  float* v;
  std::size_t width;

  void update_rows(std::size_t first, std::size_t last, float step_size,
                   const StepCoefficients& c) const {
    const std::size_t offset = first * width;
    update_elements(param + offset, grad + offset, m + offset, v + offset,
                    (last - first) * width, step_size, c);
  }
};

ArrayViews views(std::vector<float>& param, const std::vector<float>& grad,
                 std::vector<float>& m, std::vector<float>& v, std::size_t width) {
  return {param.data(), grad.data(), m.data(), v.data(), width};
}

void require_shape(const GaussianModel& params, const GaussianModel& other, const char* name) {
  other.check_consistent();
  if (other.sh_degree != params.sh_degree || other.size() != params.size())
    throw ArgumentError(std::string("adam_step: ") + name + " holds " +
                        std::to_string(other.size()) + " Gaussians at SH degree " +
                        std::to_string(other.sh_degree) + ", the model " +
                        std::to_string(params.size()) + " at degree " +
                        std::to_string(params.sh_degree));
}

}  // namespace

void AdamState::reset_like(const GaussianModel& model) {
  for (GaussianModel* moment : {&first_moment, &second_moment}) {
    moment->sh_degree = model.sh_degree;
    moment->resize(0);
    moment->resize(model.size());
  }
}

void adam_step(GaussianModel& params, const GaussianModel& grads, AdamState& state,
               const GroupLearningRates& lr, const AdamSettings& settings,
               const AdamGroupMask& active) {
  params.check_consistent();
  require_shape(params, grads, "the gradient");
  require_shape(params, state.first_moment, "the first moment");
  require_shape(params, state.second_moment, "the second moment");

  state.step += 1;
  // Python computes these in double; the kernels then see them as float scalars.
  const double t = double(state.step);
  const double bias_correction1 = 1.0 - std::pow(settings.beta1, t);
  const double bias_correction2 = 1.0 - std::pow(settings.beta2, t);
  const StepCoefficients c{float(1.0 - settings.beta1), float(settings.beta2),
                           float(1.0 - settings.beta2), float(std::sqrt(bias_correction2)),
                           float(settings.epsilon)};
  auto step_size = [&](float group_lr) { return float(double(group_lr) / bias_correction1); };
  const float means_step = step_size(lr.means), dc_step = step_size(lr.sh_dc),
              rest_step = step_size(lr.sh_rest), opacity_step = step_size(lr.opacity),
              scales_step = step_size(lr.scales), rotations_step = step_size(lr.rotations);

  GaussianModel& m = state.first_moment;
  GaussianModel& v = state.second_moment;
  const ArrayViews means = views(params.means, grads.means, m.means, v.means, 3);
  const ArrayViews scales = views(params.log_scales, grads.log_scales, m.log_scales,
                                  v.log_scales, 3);
  const ArrayViews quats = views(params.quats, grads.quats, m.quats, v.quats, 4);
  const ArrayViews opacity = views(params.opacity_logits, grads.opacity_logits,
                                   m.opacity_logits, v.opacity_logits, 1);
  const ArrayViews sh = views(params.sh, grads.sh, m.sh, v.sh,
                              std::size_t(params.sh_coefficients()) * 3);
  constexpr std::size_t kDcFloats = 3;  // band 0 leads each row: k = 0, RGB
  const std::size_t rest_floats = sh.width - kDcFloats;

  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, params.size(), kGaussiansPerTask),
      [&](const tbb::blocked_range<std::size_t>& range) {
        const std::size_t first = range.begin(), last = range.end();
        if (active.means) means.update_rows(first, last, means_step, c);
        if (active.scales) scales.update_rows(first, last, scales_step, c);
        if (active.rotations) quats.update_rows(first, last, rotations_step, c);
        if (active.opacity) opacity.update_rows(first, last, opacity_step, c);
        if (active.sh_dc || active.sh_rest) {
          // Band 0 and the rest interleave row by row: two short runs per Gaussian.
          for (std::size_t row = first; row < last; ++row) {
            const std::size_t o = row * sh.width;
            if (active.sh_dc)
              update_elements(sh.param + o, sh.grad + o, sh.m + o, sh.v + o, kDcFloats,
                              dc_step, c);
            if (active.sh_rest && rest_floats > 0)
              update_elements(sh.param + o + kDcFloats, sh.grad + o + kDcFloats,
                              sh.m + o + kDcFloats, sh.v + o + kDcFloats, rest_floats,
                              rest_step, c);
          }
        }
      },
      tbb::simple_partitioner());
}

}  // namespace splat
