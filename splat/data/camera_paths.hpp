#pragma once
// Camera paths for fly-through videos (splat-render --path): an orbit and a spiral around a
// framed centre (path_framing.hpp), and a smooth path through given views.
#include <span>
#include <vector>

#include "splat/core/camera.hpp"
#include "splat/data/path_framing.hpp"

namespace splat {

// How far the spiral's elevation swings above and below the framing's: 30 degrees, so one
// turn shows the model from well above and from below its centre.
constexpr float kSpiralElevationSwing = 0.52f;
// No path camera goes nearer the up axis than this (80 degrees), where "up" in the image
// would turn with the azimuth.
constexpr float kMaxPathElevation = 1.40f;

// `frames` cameras evenly spaced in azimuth on one turn round the framing's circle (counter-
// clockwise seen from above; frame 0 on the start side, the last one step short of it, so
// the video loops), all looking at the centre with up upright, width x height pixels,
// square pixels, the framing's vertical field of view.
std::vector<Camera> orbit_path(const PathFraming& framing, int frames, int width, int height);

// The orbit with the elevation swinging by ± kSpiralElevationSwing once per turn
// (sinusoidally: level at frame 0, highest a quarter of the way round, lowest at three
// quarters), at the same distance from the centre.
std::vector<Camera> spiral_path(const PathFraming& framing, int frames, int width, int height);

// `frames` cameras through `views` in order: frame 0 is views[0], the last frame the last
// view, and view k falls on frame k·(frames − 1)/(views − 1) exactly when that is a whole
// number (each pair of neighbours gets the same share of the frames). Between views the
// centres follow a Catmull–Rom spline through all of them (ends clamped), the rotations are
// slerped and the intrinsics, taken at width x height (Camera::resized), interpolated
// linearly. One view gives `frames` copies of it.
std::vector<Camera> interpolated_path(std::span<const Camera> views, int frames, int width, int height);

}  // namespace splat
