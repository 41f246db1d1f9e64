#pragma once
// The spec's orbit rig as cameras: positions on a golden-angle (spherical Fibonacci) spiral
// over the elevation band, so views cover the band evenly for any count; test views take the
// same spiral turned by half a golden angle, so they never coincide with training views.
#include <vector>

#include "splat/raytrace/scene_spec.hpp"
#include "splat/core/camera.hpp"

namespace splat::raytrace {

enum class Split { train, test };

// Cameras of one split, world up +Y (glTF), all looking at the target, square pixels with
// the horizontal field of view of the spec and the principal point at the image centre.
std::vector<Camera> orbit_rig_cameras(const OrbitSpec& orbit, Split split);

}  // namespace splat::raytrace
