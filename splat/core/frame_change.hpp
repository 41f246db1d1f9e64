#pragma once
// The change of frame between two sets of poses of the same views. A scene reconstructed
// with its cameras is only defined up to a similarity: pose refinement lets the training
// views' poses, and the model with them, drift by a small turn, shift and scale as a whole.
// Poses recorded in the old frame (test views, from the same calibration) are carried into
// the new one by the similarity fitted between the training views' recorded and refined
// poses, before any per-view alignment.
#include <vector>

#include <glm/glm.hpp>

#include "splat/core/camera.hpp"

namespace splat {

// x_new = scale · rotation · x_old + translation.
struct FrameChange {
  double scale = 1.0;
  glm::dmat3 rotation{1.0};
  glm::dvec3 translation{0.0};

  // `camera` (posed in the old frame) posed in the new one: it sees the moved scene as it saw
  // the old one (a scaled scene at a scaled distance projects alike), intrinsics unchanged.
  Camera applied_to(const Camera& camera) const;
  // The similarity that undoes this one.
  FrameChange inverse() const;
};

// The similarity carrying `recorded[i]` to `refined[i]`. Its rotation is the chordal mean of
// the views' changes of orientation, so it is defined for cameras in any layout (a row of
// cameras along a path included, where a fit of the centres alone leaves the turn about that
// line free); its scale and translation then fit the centres by least squares (scale 1 when
// the recorded centres coincide). Throws ArgumentError if the sizes differ or none is given.
FrameChange fit_frame_change(const std::vector<Camera>& recorded, const std::vector<Camera>& refined);

// The similarity carrying points `from[i]` to `to[i]` by least squares (Umeyama 1991): for
// cameras' centres, where the orientations are what is then measured against it. Throws
// ArgumentError if the sizes differ, fewer than three points are given, or `from`'s coincide.
FrameChange fit_point_similarity(const std::vector<glm::dvec3>& from, const std::vector<glm::dvec3>& to);

}  // namespace splat
