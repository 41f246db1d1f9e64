#include "splat/optim/adam.hpp"

#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "splat/core/error.hpp"
#include "splat/core/simd.hpp"

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

// The same update over the first `columns` floats of rows `width` floats apart, whose columns
// have their own step sizes (`step_sizes[j]` for column j): every element gets exactly
// update_elements' arithmetic, in one loop the compiler vectorises across the row instead of
// a short loop per run of columns.
inline void update_rows_by_column(float* __restrict param, const float* __restrict grad,
                                  float* __restrict m, float* __restrict v, std::size_t rows,
                                  std::size_t width, std::size_t columns, const float* __restrict step_sizes,
                                  const StepCoefficients& c) {
  for (std::size_t row = 0; row < rows; ++row) {
    const std::size_t o = row * width;
    for (std::size_t j = 0; j < columns; ++j) {
      const float g = grad[o + j];
      const float m_new = m[o + j] + c.one_minus_beta1 * (g - m[o + j]);
      const float v_new = v[o + j] * c.beta2 + c.one_minus_beta2 * g * g;
      m[o + j] = m_new;
      v[o + j] = v_new;
      const float denom = std::sqrt(v_new) / c.bias_correction2_sqrt + c.epsilon;
      param[o + j] = param[o + j] + (-step_sizes[j]) * (m_new / denom);
    }
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

// One parameter group's arrays across the four models.
ArrayViews views(const ParameterGroup& group, GaussianModel& params, const GaussianModel& grads,
                 AdamState& state) {
  return {group.of(params).data(), group.of(grads).data(), group.of(state.first_moment).data(),
          group.of(state.second_moment).data(), group.width(params.sh_degree)};
}

// A group stepped as a whole: its arrays, step size and switch.
struct GroupStep {
  ArrayViews arrays;
  float step_size;
  bool active;
};

void require_shape(const GaussianModel& params, const GaussianModel& other, const char* name) {
  other.check_consistent();
  if (other.sh_degree != params.sh_degree || other.size() != params.size())
    throw ArgumentError(std::string("adam_step: ") + name + " holds " +
                        std::to_string(other.size()) + " Gaussians at SH degree " +
                        std::to_string(other.sh_degree) + ", the model " +
                        std::to_string(params.size()) + " at degree " +
                        std::to_string(params.sh_degree));
}

void require_size(const GaussianModel& params, const ShGradientFactors& factors) {
  if (factors.size() != params.size())
    throw ArgumentError("adam_step: the SH gradient's factors hold " + std::to_string(factors.size()) +
                        " Gaussians, the model " + std::to_string(params.size()));
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
               const AdamGroupMask& active, const ShGradientFactors* sh_factors) {
  params.check_consistent();
  require_shape(params, grads, "the gradient");
  if (sh_factors) require_size(params, *sh_factors);
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

  // Every group but the SH coefficients is one Adam group; the SH group is two (band 0 and
  // the rest, at different rates), stepped below.
  std::vector<GroupStep> whole;
  ArrayViews sh{};
  for (const ParameterGroup& group : kParameterGroups) {
    const ArrayViews arrays = views(group, params, grads, state);
    switch (group.id) {
      case ParameterGroupId::kMeans: whole.push_back({arrays, step_size(lr.means), active.means}); break;
      case ParameterGroupId::kLogScales: whole.push_back({arrays, step_size(lr.scales), active.scales}); break;
      case ParameterGroupId::kQuats: whole.push_back({arrays, step_size(lr.rotations), active.rotations}); break;
      case ParameterGroupId::kOpacityLogits: whole.push_back({arrays, step_size(lr.opacity), active.opacity}); break;
      case ParameterGroupId::kSh: sh = arrays; break;
    }
  }
  const float dc_step = step_size(lr.sh_dc), rest_step = step_size(lr.sh_rest);
  constexpr std::size_t kDcFloats = 3;  // band 0 leads each row: k = 0, RGB
  // The row's columns that are stepped: the bands up to active.sh_degree.
  const std::size_t stepped = std::min(
      sh.width, std::size_t(3 * sh_coefficient_count(std::clamp(active.sh_degree, 0, params.sh_degree))));
  const std::size_t rest_floats = stepped - std::min(kDcFloats, stepped);
  std::vector<float> sh_steps(sh.width, rest_step);  // per column of an SH row
  std::fill(sh_steps.begin(), sh_steps.begin() + std::min(kDcFloats, sh.width), dc_step);

  // SH rows first .. last − 1, their gradient rows at `grad` (row `first` first).
  auto update_sh_rows = [&](std::size_t first, std::size_t last, const float* grad) {
    const std::size_t o = first * sh.width;
    if (active.sh_dc && active.sh_rest) {
      update_rows_by_column(sh.param + o, grad, sh.m + o, sh.v + o, last - first, sh.width, stepped,
                            sh_steps.data(), c);
    } else if (active.sh_dc || active.sh_rest) {
      // Band 0 and the rest interleave row by row: two short runs per Gaussian.
      for (std::size_t row = first; row < last; ++row) {
        const std::size_t r = row * sh.width;
        const float* g = grad + (row - first) * sh.width;
        if (active.sh_dc) update_elements(sh.param + r, g, sh.m + r, sh.v + r, kDcFloats, dc_step, c);
        if (active.sh_rest && rest_floats > 0)
          update_elements(sh.param + r + kDcFloats, g + kDcFloats, sh.m + r + kDcFloats, sh.v + r + kDcFloats,
                          rest_floats, rest_step, c);
      }
    }
  };

  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, params.size(), kGaussiansPerTask),
      [&](const tbb::blocked_range<std::size_t>& range) {
        const std::size_t first = range.begin(), last = range.end();
        for (const GroupStep& group : whole)
          if (group.active) group.arrays.update_rows(first, last, group.step_size, c);
        if (!active.sh_dc && !active.sh_rest) return;
        if (!sh_factors) {
          update_sh_rows(first, last, sh.grad + first * sh.width);
          return;
        }
        // The rows formed from their factors, kLanes at a time, as the step reaches them.
        alignas(64) float rows[simd::kLanes * kMaxShFloats];
        for (std::size_t row = first; row < last; row += simd::kLanes) {
          const std::size_t end = std::min(last, row + simd::kLanes);
          sh_factors->expand(row, int(end - row), int(sh.width), rows);
          update_sh_rows(row, end, rows);
        }
      },
      tbb::simple_partitioner());
}

}  // namespace splat
