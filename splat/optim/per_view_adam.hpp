#pragma once
// Adam over a small block of parameters per training view (a view's pose correction, its
// exposure map). A view's block moves only on the iterations that train on that view, so each
// view keeps its own moments and step count. A block may be cut into parts stepped at their
// own rates (a pose correction's rotation and translation).
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "splat/optim/flat_adam.hpp"

namespace splat {

class PerViewAdam {
 public:
  PerViewAdam() = default;
  // `part_sizes`: the sizes of the parts of one view's block, in order. `name` (e.g.
  // "pose corrections") names the state in restore()'s errors.
  PerViewAdam(std::size_t views, std::vector<std::size_t> part_sizes, FlatAdamSettings settings, std::string name);

  std::size_t views() const { return steps_.size(); }
  std::size_t values_per_view() const { return values_per_view_; }
  // Every view's block, views × values_per_view().
  std::vector<float>& parameters() { return parameters_; }
  const std::vector<float>& parameters() const { return parameters_; }
  std::span<float> parameters(std::size_t view) { return {&parameters_[view * values_per_view_], values_per_view_}; }
  std::span<const float> parameters(std::size_t view) const {
    return {&parameters_[view * values_per_view_], values_per_view_};
  }

  // One Adam step of view `view`'s block: `grad` has values_per_view() numbers,
  // `learning_rates` one per part.
  void step(std::size_t view, std::span<const float> grad, std::span<const float> learning_rates);

  // The state for checkpoints: Adam's moments laid out as the parameters, one step count per view.
  std::vector<float> first_moments() const;
  std::vector<float> second_moments() const;
  const std::vector<long long>& steps() const { return steps_; }
  // Restores it; throws ArgumentError naming the state if a size does not match or a value is
  // not finite.
  void restore(const std::vector<float>& parameters, const std::vector<float>& first_moments,
               const std::vector<float>& second_moments, const std::vector<long long>& steps);

 private:
  std::vector<float> moments(const std::vector<float>& (FlatAdam::*moment)() const) const;

  std::string name_;
  std::vector<std::size_t> part_sizes_;
  std::size_t values_per_view_ = 0;
  std::vector<float> parameters_;
  std::vector<FlatAdam> adams_;  // [view × parts + part]
  std::vector<long long> steps_;
};

}  // namespace splat
