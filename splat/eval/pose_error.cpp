#include "splat/eval/pose_error.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "splat/core/error.hpp"
#include "splat/core/frame_change.hpp"

namespace splat {

PoseError pose_error(const std::vector<Camera>& estimated, const std::vector<Camera>& truth) {
  if (estimated.size() != truth.size())
    throw ArgumentError("pose error: " + std::to_string(estimated.size()) + " estimated cameras against " +
                        std::to_string(truth.size()) + " true ones");
  const int n = int(truth.size());
  if (n < 3) throw ArgumentError("pose error: needs at least 3 cameras");
  std::vector<glm::dvec3> from(n), to(n);
  for (int i = 0; i < n; ++i) {
    from[i] = glm::dvec3(estimated[i].center_in_world());
    to[i] = glm::dvec3(truth[i].center_in_world());
  }
  const FrameChange fit = fit_point_similarity(from, to);  // x_truth = s·G·x_estimated + g

  PoseError e;
  e.scale = fit.scale;
  for (int i = 0; i < n; ++i) {
    // x_cam = R_est·(x_est − c) and x_est = Gᵀ·(x_truth − g)/s: in the truth's frame the
    // estimated camera's rotation is R_est·Gᵀ.
    const glm::dmat3 relative = glm::dmat3(estimated[i].camera_from_world_rotation) * glm::transpose(fit.rotation) *
                                glm::transpose(glm::dmat3(truth[i].camera_from_world_rotation));
    // ‖R − I‖ = 2√2·sin(θ/2) for a rotation by θ: unlike the trace's arccos, exact near θ = 0
    // for rotations stored in float.
    double squared = 0;
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) {
        const double d = relative[c][r] - (r == c ? 1.0 : 0.0);
        squared += d * d;
      }
    const double half_sine = std::min(1.0, std::sqrt(squared) / (2.0 * std::sqrt(2.0)));
    const double rotation_deg = 2.0 * std::asin(half_sine) * 180.0 / 3.14159265358979323846;
    const double translation = glm::length(fit.scale * (fit.rotation * from[i]) + fit.translation - to[i]);
    e.mean_rotation_deg += rotation_deg / n;
    e.max_rotation_deg = std::max(e.max_rotation_deg, rotation_deg);
    e.mean_translation += translation / n;
    e.max_translation = std::max(e.max_translation, translation);
  }
  return e;
}

}  // namespace splat
