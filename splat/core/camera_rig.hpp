#pragma once
// Where a set of cameras looks: the point their optical axes pass closest to, how far the
// cameras stand from it, and how large a ball around it every one of them sees whole. The
// random initialisation and the scene's bounds follow from these instead of a fixed cube.
#include <optional>
#include <span>

#include <glm/glm.hpp>

#include "splat/core/camera.hpp"

namespace splat {

struct CameraRig {
  glm::vec3 focus{0.0f};  // least-squares point nearest every optical axis
  float distance = 0;     // median distance of the camera centres from the focus
  // The radius of the ball around the focus that lies inside every camera's view: per camera
  // D·sin(φ − θ), with D its distance, φ its narrower half field of view and θ the angle
  // between its axis and the focus; the smallest over the cameras (0 when one does not see
  // the focus at all).
  float seen_radius = 0;
};

// The rig of `cameras`, or nothing when their axes do not converge in front of them: fewer
// than two cameras, axes (nearly) parallel, as in a forward-facing capture, or a focus
// behind most of the cameras, as in a panorama looking outwards.
std::optional<CameraRig> converging_rig(std::span<const Camera> cameras);

// The unit direction `camera` looks along (its optical axis, +z of its frame), in world
// coordinates.
glm::vec3 optical_axis(const Camera& camera);

// Whether world point `p` lies in front of `camera` and projects inside its image.
bool in_view(const Camera& camera, const glm::vec3& p);

}  // namespace splat
