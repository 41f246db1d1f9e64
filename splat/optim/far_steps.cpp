#include "splat/optim/far_steps.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "splat/core/error.hpp"

namespace splat {

void scale_far_steps(std::span<float> means, std::span<const float> before, const FarSteps& far) {
  if (means.size() != before.size() || means.size() % 3 != 0)
    throw ArgumentError("scale_far_steps: " + std::to_string(means.size()) + " means but " +
                        std::to_string(before.size()) + " starting values");
  if (!far.active()) return;
  if (!(far.limit >= far.distance))
    throw ArgumentError("scale_far_steps: limit " + std::to_string(far.limit) + " is below the distance " +
                        std::to_string(far.distance));
  for (std::size_t i = 0; i < means.size(); i += 3) {
    const glm::vec3 start(before[i], before[i + 1], before[i + 2]);
    const float r = glm::length(start - far.centre);
    if (!(r > far.distance)) continue;
    const float factor = std::pow(std::min(r, far.limit) / far.distance, far.exponent);
    for (int a = 0; a < 3; ++a) means[i + a] = before[i + a] + factor * (means[i + a] - before[i + a]);
  }
}

}  // namespace splat
