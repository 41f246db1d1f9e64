#include "splat/optim/per_view_adam.hpp"

#include <cmath>
#include <numeric>
#include <utility>

#include "splat/core/error.hpp"

namespace splat {

PerViewAdam::PerViewAdam(std::size_t views, std::vector<std::size_t> part_sizes, FlatAdamSettings settings,
                         std::string name)
    : name_(std::move(name)),
      part_sizes_(std::move(part_sizes)),
      values_per_view_(std::accumulate(part_sizes_.begin(), part_sizes_.end(), std::size_t{0})),
      parameters_(views * values_per_view_, 0.0f),
      steps_(views, 0) {
  adams_.reserve(views * part_sizes_.size());
  for (std::size_t v = 0; v < views; ++v)
    for (std::size_t size : part_sizes_) adams_.emplace_back(size, settings);
}

void PerViewAdam::step(std::size_t view, std::span<const float> grad, std::span<const float> learning_rates) {
  if (grad.size() != values_per_view_ || learning_rates.size() != part_sizes_.size())
    throw ArgumentError(name_ + ": a step needs " + std::to_string(values_per_view_) + " gradients and " +
                        std::to_string(part_sizes_.size()) + " learning rates");
  std::size_t offset = 0;
  for (std::size_t part = 0; part < part_sizes_.size(); ++part) {
    const std::size_t size = part_sizes_[part];
    adams_[view * part_sizes_.size() + part].step(parameters(view).subspan(offset, size), grad.subspan(offset, size),
                                                  learning_rates[part]);
    offset += size;
  }
  ++steps_[view];
}

std::vector<float> PerViewAdam::moments(const std::vector<float>& (FlatAdam::*moment)() const) const {
  std::vector<float> out;
  out.reserve(parameters_.size());
  for (const FlatAdam& adam : adams_) {  // views in order, each view's parts in order
    const std::vector<float>& m = (adam.*moment)();
    out.insert(out.end(), m.begin(), m.end());
  }
  return out;
}

std::vector<float> PerViewAdam::first_moments() const { return moments(&FlatAdam::first_moment); }
std::vector<float> PerViewAdam::second_moments() const { return moments(&FlatAdam::second_moment); }

void PerViewAdam::restore(const std::vector<float>& parameters, const std::vector<float>& first_moments,
                          const std::vector<float>& second_moments, const std::vector<long long>& steps) {
  const std::size_t n = parameters_.size();
  if (parameters.size() != n || first_moments.size() != n || second_moments.size() != n ||
      steps.size() != views())
    throw ArgumentError(name_ + ": expected " + std::to_string(views()) + " views of " +
                        std::to_string(values_per_view_) + " values");
  for (const std::vector<float>* a : {&parameters, &first_moments, &second_moments})
    for (float x : *a)
      if (!std::isfinite(x)) throw ArgumentError(name_ + ": a value is not finite");
  for (long long s : steps)
    if (s < 0) throw ArgumentError(name_ + ": a negative step count");
  parameters_ = parameters;
  steps_ = steps;
  std::size_t offset = 0;
  for (std::size_t i = 0; i < adams_.size(); ++i) {
    FlatAdam& adam = adams_[i];
    for (std::size_t k = 0; k < adam.size(); ++k) {
      adam.first_moment()[k] = first_moments[offset + k];
      adam.second_moment()[k] = second_moments[offset + k];
    }
    adam.set_steps(steps[i / part_sizes_.size()]);
    offset += adam.size();
  }
}

}  // namespace splat
