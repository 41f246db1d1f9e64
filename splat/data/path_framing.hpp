#pragma once
// Where a fly-through circles and how it frames the model: from the model's contents alone,
// or from the cameras a scene was captured with, so the orbit matches the capture.
#include <optional>
#include <span>

#include <glm/glm.hpp>

#include "splat/core/camera.hpp"
#include "splat/core/rays.hpp"

namespace splat {

// The circle a path's cameras move on: about the axis through `center` along `up`, at
// `distance` from the centre and `elevation` above the plane through it perpendicular to
// `up`, starting on the `start` side; every camera looks at the centre.
struct PathFraming {
  glm::vec3 center{0.0f};
  glm::vec3 up{0.0f, 0.0f, 1.0f};     // unit
  glm::vec3 start{0.0f, -1.0f, 0.0f}; // unit, perpendicular to up
  float distance = 4.0f;
  float elevation = 0.35f;            // radians
  float fov_y = 0.7f;                 // vertical field of view, radians
};

// The field of view and elevation a path has when nothing says otherwise: a moderate lens,
// looking down on the content from 20 degrees, as a product shot would.
constexpr float kDefaultPathFovY = 0.70f;       // 40 degrees
constexpr float kDefaultPathElevation = 0.35f;  // 20 degrees

// Per axis, the weighted `tail` and 1 − `tail` quantiles of the points `xyz` [N, 3]
// (weights [N], >= 0, e.g. opacities; empty: all 1): the box most of the content lies in,
// which a few far floaters, or many faint ones, do not stretch. Nothing when no point has
// weight.
std::optional<AxisAlignedBox> robust_box(std::span<const float> xyz, std::span<const float> weights,
                                         float tail = 0.02f);

// Frames `box` for images of `aspect` = width / height: world `up`, the default elevation and
// field of view, and the distance at which the box's bounding ball just fits the narrower
// side of the image.
PathFraming frame_box(const AxisAlignedBox& box, const glm::vec3& up, float aspect);

// Frames a path like the capture `cameras` (at least one): the point nearest all their optical
// axes (converging_rig; else `content`'s centre), their up (capture_up), their mean distance
// from that centre and mean elevation above it, the first camera's side and vertical field of
// view.
PathFraming frame_from_cameras(std::span<const Camera> cameras, const AxisAlignedBox& content);

// The capture's up direction. People hold cameras level, so each camera's x axis (image right)
// is horizontal: up is the direction most nearly perpendicular to all of them (the smallest
// eigenvector of their scatter), signed to agree with the cameras' mean up (−y in OpenCV
// axes), when the images stand upright about it. The mean up alone tilts towards whichever side more cameras stand on. When the right
// vectors do not span a plane (images stored turned by 90 degrees, as phones do, or at mixed
// rolls) and the cameras converge on `focus`, the normal of the plane the camera centres are
// flattest in (a walk round the object), signed by the images' up or else towards the
// cameras' side of the focus. Else (a capture facing one way: no focus) the mean up;
// `fallback` when even that cancels out.
glm::vec3 capture_up(std::span<const Camera> cameras, const std::optional<glm::vec3>& focus,
                     const glm::vec3& fallback);

}  // namespace splat
