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

  // The maps and their optimiser, as checkpoints store and restore them: six numbers per view.
  const PerViewAdam& state() const { return adam_; }
  PerViewAdam& state() { return adam_; }

 private:
  PerViewAdam adam_;  // per view: kExposureValues numbers
};

}  // namespace splat
