#include "splat/nerf/nerf_model.hpp"

#include <algorithm>

namespace splat {

float NerfSettings::coarse_step() const {
  const int in_box = unbounded ? std::max(1, coarse_samples / 2) : std::max(1, coarse_samples);
  return glm::length(box.hi - box.lo) / float(in_box);
}

}  // namespace splat
