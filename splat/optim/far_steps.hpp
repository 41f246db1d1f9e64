#pragma once
// Position steps that grow with distance beyond the cameras.
//
// The position learning rate is one length for every Gaussian (scaled by the scene extent,
// the cameras' spread). A Gaussian k times further from the cameras moves k times less on
// screen for the same step, and its depth is resolved k² times more coarsely, so content far
// outside the camera rig (a wall, a horizon) barely moves from where it started within a
// short run. Mip-NeRF 360 meets the same problem by contracting space beyond the cameras:
// its coordinates shrink like 1/r tangentially and 1/r² radially there. Here, more simply,
// a Gaussian at distance r from the scene's centre beyond `distance` D has its step
// multiplied by (min(r, limit) / D)^exponent, measured where it starts the step; within D
// the step is untouched. The limit (the far end of the random start, where the background
// shell lies) keeps the factor bounded: without it a Gaussian pushed outwards takes ever
// larger steps and runs away to infinity within a few iterations.
#include <span>

#include <glm/glm.hpp>

namespace splat {

struct FarSteps {
  glm::vec3 centre{0.0f};
  float distance = 0;    // D; 0 = off
  float limit = 0;       // the largest r the factor grows to (at least D)
  float exponent = 0;    // 0 = off
  bool active() const { return distance > 0 && exponent > 0; }
};

// Rescales the step each Gaussian just took, from `before` to `means` (both [N, 3]): means
// = before + f·(means − before) with f = (min(r, limit) / D)^exponent where r = |before −
// centre| > D. Gaussians within D are left bit for bit as they are. ArgumentError when the
// sizes differ or the limit is below D.
void scale_far_steps(std::span<float> means, std::span<const float> before, const FarSteps& far);

}  // namespace splat
