#pragma once
// How far a set of camera poses is from the true ones, up to the frame they live in. Poses
// recovered from photographs are only defined up to a similarity (a model and its cameras can
// be moved, turned and scaled together without changing any image), so the estimated cameras'
// centres are first fitted to the true ones by a similarity (Umeyama 1991, least squares), and
// the errors are measured after it: the usual absolute-trajectory protocol.
#include <vector>

#include "splat/core/camera.hpp"

namespace splat {

struct PoseError {
  double mean_rotation_deg = 0, max_rotation_deg = 0;  // angle between estimated and true orientation
  double mean_translation = 0, max_translation = 0;    // distance between centres, in the truth's units
  double scale = 1;                                    // the fitted similarity's scale
};

// `estimated[i]` against `truth[i]`; throws ArgumentError if the sizes differ or fewer than
// three cameras are given (a similarity needs three centres not on one line).
PoseError pose_error(const std::vector<Camera>& estimated, const std::vector<Camera>& truth);

}  // namespace splat
