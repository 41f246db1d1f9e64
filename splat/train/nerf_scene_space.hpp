#pragma once
// Where the NeRF samples, from what the dataset says about the scene (scene_space.hpp): the
// box of its point cloud (COLMAP), or the region its cameras look at; unbounded (the space
// outside the box contracted) when the views show a background that reaches their frame,
// bounded when they show an object on a plain background (background_left_out).
#include "splat/data/dataset.hpp"
#include "splat/nerf/scene_space.hpp"

namespace splat {

// - A point cloud: its bounding box, 5 % wider on every side, bounded (the points cover
//   what the photographs show; a ray past them meets the background colour).
// - Converging cameras (camera_rig.hpp) round an object on its own: the cube round their
//   focus whose half size is 1.1 × the radius of the ball every camera sees whole (lego400:
//   ±1.50, the box the NeRF-synthetic objects are known to fit in).
// - Converging cameras whose images show a background: unbounded, the inner cube round the
//   focus holding every camera with 10 % to spare (Mip-NeRF 360 puts its cameras inside the
//   uncontracted ball likewise); everything farther is contracted.
// - Otherwise (parallel or outward-looking cameras, no data) `fallback`, bounded.
SceneSpace scene_space_from_data(const Dataset& dataset, const AxisAlignedBox& fallback);

}  // namespace splat
