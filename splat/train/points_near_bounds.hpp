#pragma once
// Where each training camera's scene begins, as the structure-from-motion points say: the
// depth in front of which (almost) none of the points inside its frame lie. A Gaussian much
// nearer than that to a camera whose frame holds it sits in space the capture shows empty,
// between the camera and everything the photographs were matched on: on real captures that
// is where the floaters that spoil a passing test view grow (bench/HISTORY.md, issue 40:
// real_cup's close-up view 78 lost 4.5 dB to 772 such Gaussians, seen by 10-35 training
// views each, at a fifth to a quarter of their depth).
#include <glm/glm.hpp>
#include <vector>

#include "splat/core/camera.hpp"
#include "splat/data/dataset.hpp"

namespace splat {

struct CameraNearBound {
  Camera camera;
  float near_depth = 0;  // the points' low quantile of depth in this camera
};

// The quantile of the depths taken as a view's near bound: the nearest 1 % of a view's points
// are left out, since a sparse reconstruction holds a few stray points as well.
constexpr float kNearPointQuantile = 0.01f;
// Fewer points than this inside a view's frame give it no bound.
constexpr std::size_t kMinPointsForNearBound = 20;

// One bound per training view with enough points in its frame; none without a point cloud.
std::vector<CameraNearBound> points_near_bounds(const Dataset& dataset);

// Whether `position` lies inside the frame of one of `bounds`' cameras at a depth below
// `factor` × that camera's near depth.
bool in_front_of_points(const std::vector<CameraNearBound>& bounds, const glm::vec3& position, float factor);

}  // namespace splat
