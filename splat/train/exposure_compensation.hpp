#pragma once
// Per-view exposure compensation (--exposure-compensation): each training view's render
// passes through its own affine colour map (splat/optim/exposure.hpp) before the loss, and
// the maps are optimised with the scene. Their mean over the views is held at the identity,
// so the model itself keeps the views' mean exposure: test views are rendered and scored
// without a map.
#include <cstddef>
#include <vector>

#include "splat/core/image.hpp"
#include "splat/optim/exposure.hpp"
#include "splat/optim/per_view_adam.hpp"

namespace splat {

class ExposureCompensation {
 public:
  ExposureCompensation() = default;
  explicit ExposureCompensation(std::size_t views);

  std::size_t views() const { return adam_.views(); }
  // View `view`'s six numbers (log gains, then offsets).
  const float* parameters(std::size_t view) const { return adam_.parameters(view).data(); }

  // `out` = `rendered` through view `view`'s map.
  void apply(std::size_t view, const Image& rendered, Image& out) const;
  // `v_image` holds ∂L/∂out on entry and ∂L/∂rendered on return; then one Adam step of the
  // view's map, and every map moved so that their mean stays the identity.
  void backward_and_step(std::size_t view, const Image& rendered, Image& v_image, float lr);

  // The state for checkpoints: six numbers per view, Adam's moments alike, each view's steps.
  const std::vector<float>& parameters() const { return adam_.parameters(); }
  std::vector<float> first_moments() const { return adam_.first_moments(); }
  std::vector<float> second_moments() const { return adam_.second_moments(); }
  const std::vector<long long>& steps() const { return adam_.steps(); }
  // Restores it; throws ArgumentError if the sizes do not match views() or a value is not finite.
  void restore(const std::vector<float>& parameters, const std::vector<float>& first_moments,
               const std::vector<float>& second_moments, const std::vector<long long>& steps) {
    adam_.restore(parameters, first_moments, second_moments, steps);
  }

 private:
  PerViewAdam adam_;  // per view: kExposureValues numbers
};

}  // namespace splat
