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
  float average_decay;          // β_avg, used while a parameter average is kept
};

// Adam's update of one element, in PyTorch's order term by term (see adam.hpp): the new
// moments and the step to add to the parameter. Taken by value, so the loops below keep their
// restrict pointers and the compiler vectorises them.
struct ElementStep {
  float m, v, step;
};
inline ElementStep adam_element(float g, float m, float v, float step_size, const StepCoefficients& c) {
  const float m_new = m + c.one_minus_beta1 * (g - m);
  const float v_new = v * c.beta2 + c.one_minus_beta2 * g * g;
  const float denom = std::sqrt(v_new) / c.bias_correction2_sqrt + c.epsilon;
  return {m_new, v_new, (-step_size) * (m_new / denom)};
}

// The Adam update of `count` consecutive elements, element i at step size step_size_of(i)
// (lr / (1 − β1ᵗ) of its group), and with kAverage the parameter average's offsets moved with
// them (adam.hpp). The step size comes from a callable so that one loop body serves a run of
// one group and a row of several; either way the compiler vectorises it.
template <bool kAverage, typename StepSizeOf>
[[gnu::always_inline]] inline void update_run(float* __restrict param, const float* __restrict grad,
                                              float* __restrict m, float* __restrict v, float* __restrict offset,
                                              std::size_t count, StepSizeOf step_size_of, const StepCoefficients& c) {
  for (std::size_t i = 0; i < count; ++i) {
    const ElementStep e = adam_element(grad[i], m[i], v[i], step_size_of(i), c);
    m[i] = e.m;
    v[i] = e.v;
    param[i] = param[i] + e.step;
    if constexpr (kAverage) offset[i] = c.average_decay * (offset[i] - e.step);
  }
}

// `count` consecutive elements with one step size.
template <bool kAverage>
void update_elements(float* __restrict param, const float* __restrict grad, float* __restrict m,
                     float* __restrict v, float* __restrict offset, std::size_t count, float step_size,
                     const StepCoefficients& c) {
  update_run<kAverage>(param, grad, m, v, offset, count, [step_size](std::size_t) { return step_size; }, c);
}

// The first `columns` floats of rows `width` floats apart, whose columns have their own step
// sizes (`step_sizes[j]` for column j): one loop across each row instead of a short loop per
// run of columns.
template <bool kAverage>
void update_rows_by_column(float* __restrict param, const float* __restrict grad, float* __restrict m,
                           float* __restrict v, float* __restrict offset, std::size_t rows, std::size_t width,
                           std::size_t columns, const float* __restrict step_sizes, const StepCoefficients& c) {
  for (std::size_t row = 0; row < rows; ++row) {
    const std::size_t o = row * width;
    update_run<kAverage>(param + o, grad + o, m + o, v + o, kAverage ? offset + o : nullptr, columns,
                         [step_sizes](std::size_t j) { return step_sizes[j]; }, c);
  }
}

// Views of one parameter array across the models, with its row width (offset: the average's,
// null without one).
struct ArrayViews {
  float* param;
  const float* grad;
  float* m;
  float* v;
  float* offset;
  std::size_t width;

  // Rows first .. last − 1 at `step_size`.
  template <bool kAverage>
  void update_rows(std::size_t first, std::size_t last, float step_size, const StepCoefficients& c) const {
    const std::size_t o = first * width;
    update_elements<kAverage>(param + o, grad + o, m + o, v + o, kAverage ? offset + o : nullptr,
                              (last - first) * width, step_size, c);
  }
  // Columns `begin` .. `end` − 1 of row `row`, whose gradient row is at `g`.
  template <bool kAverage>
  void update_columns(std::size_t row, std::size_t begin, std::size_t end, const float* g, float step_size,
                      const StepCoefficients& c) const {
    const std::size_t o = row * width + begin;
    update_elements<kAverage>(param + o, g + begin, m + o, v + o, kAverage ? offset + o : nullptr, end - begin,
                              step_size, c);
  }
};

// One parameter group's arrays across the models.
ArrayViews views(const ParameterGroup& group, GaussianModel& params, const GaussianModel& grads,
                 AdamState& state) {
  return {group.of(params).data(),
          group.of(grads).data(),
          group.of(state.first_moment).data(),
          group.of(state.second_moment).data(),
          state.averaging() ? group.of(state.average_offset).data() : nullptr,
          group.width(params.sh_degree)};
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

// What one step does to every group, set up by adam_step.
struct StepPlan {
  std::vector<GroupStep> whole;  // every group but the SH coefficients
  ArrayViews sh;                 // the SH group: band 0 and the rest at their own rates
  float dc_step, rest_step;
  std::size_t stepped;            // the SH row's columns stepped: the bands up to the active degree
  std::vector<float> sh_steps;    // per column of an SH row
  AdamGroupMask active;
  const ShGradientFactors* sh_factors;
  StepCoefficients c;

  static constexpr std::size_t kDcFloats = 3;  // band 0 leads each row: k = 0, RGB

  // SH rows first .. last − 1, their gradient rows at `grad` (row `first` first).
  template <bool kAverage>
  void update_sh_rows(std::size_t first, std::size_t last, const float* grad) const {
    if (active.sh_dc && active.sh_rest) {
      const std::size_t o = first * sh.width;
      update_rows_by_column<kAverage>(sh.param + o, grad, sh.m + o, sh.v + o, kAverage ? sh.offset + o : nullptr,
                                      last - first, sh.width, stepped, sh_steps.data(), c);
    } else if (active.sh_dc || active.sh_rest) {
      // Band 0 and the rest interleave row by row: two short runs per Gaussian.
      const std::size_t dc_end = std::min(kDcFloats, stepped);
      for (std::size_t row = first; row < last; ++row) {
        const float* g = grad + (row - first) * sh.width;
        if (active.sh_dc) sh.update_columns<kAverage>(row, 0, dc_end, g, dc_step, c);
        if (active.sh_rest && stepped > dc_end) sh.update_columns<kAverage>(row, dc_end, stepped, g, rest_step, c);
      }
    }
  }

  // Gaussians first .. last − 1, every active group.
  template <bool kAverage>
  void update(std::size_t first, std::size_t last) const {
    for (const GroupStep& group : whole)
      if (group.active) group.arrays.update_rows<kAverage>(first, last, group.step_size, c);
    if (!active.sh_dc && !active.sh_rest) return;
    if (!sh_factors) {
      update_sh_rows<kAverage>(first, last, sh.grad + first * sh.width);
      return;
    }
    // The rows formed from their factors, kLanes at a time, as the step reaches them.
    alignas(64) float rows[simd::kLanes * kMaxShFloats];
    for (std::size_t row = first; row < last; row += simd::kLanes) {
      const std::size_t end = std::min(last, row + simd::kLanes);
      sh_factors->expand(row, int(end - row), int(sh.width), rows);
      update_sh_rows<kAverage>(row, end, rows);
    }
  }
};

}  // namespace

void AdamState::reset_like(const GaussianModel& model) {
  for (GaussianModel* moment : {&first_moment, &second_moment}) {
    moment->sh_degree = model.sh_degree;
    moment->resize(0);
    moment->resize(model.size());
  }
  average_offset = GaussianModel{};
  average_start.reset();
}

void AdamState::start_average(const GaussianModel& model, int iteration) {
  average_offset = GaussianModel{};
  average_offset.sh_degree = model.sh_degree;
  average_offset.resize(model.size());
  average_start = iteration;
}

GaussianModel AdamState::averaged(const GaussianModel& params) const {
  GaussianModel average = params;
  if (averaging()) average.add(average_offset);
  return average;
}

std::vector<GaussianModel*> AdamState::rows() {
  std::vector<GaussianModel*> out{&first_moment, &second_moment};
  if (averaging()) out.push_back(&average_offset);
  return out;
}

void adam_step(GaussianModel& params, const GaussianModel& grads, AdamState& state,
               const GroupLearningRates& lr, const AdamSettings& settings,
               const AdamGroupMask& active, const ShGradientFactors* sh_factors) {
  params.check_consistent();
  require_shape(params, grads, "the gradient");
  if (sh_factors) require_size(params, *sh_factors);
  require_shape(params, state.first_moment, "the first moment");
  require_shape(params, state.second_moment, "the second moment");
  if (state.averaging()) require_shape(params, state.average_offset, "the parameter average");

  state.step += 1;
  // Python computes these in double; the kernels then see them as float scalars.
  const double t = double(state.step);
  const double bias_correction1 = 1.0 - std::pow(settings.beta1, t);
  const double bias_correction2 = 1.0 - std::pow(settings.beta2, t);
  StepPlan plan;
  plan.c = {float(1.0 - settings.beta1), float(settings.beta2), float(1.0 - settings.beta2),
            float(std::sqrt(bias_correction2)), float(settings.epsilon), float(settings.average_decay)};
  auto step_size = [&](float group_lr) { return float(double(group_lr) / bias_correction1); };

  for (const ParameterGroup& group : kParameterGroups) {
    const ArrayViews arrays = views(group, params, grads, state);
    switch (group.id) {
      case ParameterGroupId::kMeans: plan.whole.push_back({arrays, step_size(lr.means), active.means}); break;
      case ParameterGroupId::kLogScales: plan.whole.push_back({arrays, step_size(lr.scales), active.scales}); break;
      case ParameterGroupId::kQuats: plan.whole.push_back({arrays, step_size(lr.rotations), active.rotations}); break;
      case ParameterGroupId::kOpacityLogits: plan.whole.push_back({arrays, step_size(lr.opacity), active.opacity}); break;
      case ParameterGroupId::kSh: plan.sh = arrays; break;
    }
  }
  plan.dc_step = step_size(lr.sh_dc);
  plan.rest_step = step_size(lr.sh_rest);
  plan.stepped = std::min(plan.sh.width,
                          std::size_t(3 * sh_coefficient_count(std::clamp(active.sh_degree, 0, params.sh_degree))));
  plan.sh_steps.assign(plan.sh.width, plan.rest_step);
  std::fill(plan.sh_steps.begin(), plan.sh_steps.begin() + std::min(StepPlan::kDcFloats, plan.sh.width), plan.dc_step);
  plan.active = active;
  plan.sh_factors = sh_factors;

  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, params.size(), kGaussiansPerTask),
      [&](const tbb::blocked_range<std::size_t>& range) {
        if (state.averaging()) plan.update<true>(range.begin(), range.end());
        else plan.update<false>(range.begin(), range.end());
      },
      tbb::simple_partitioner());
}

}  // namespace splat
