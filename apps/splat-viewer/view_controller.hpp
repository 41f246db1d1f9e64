#pragma once
// The viewer's camera: orbit about a target, pan, zoom, fly, reset, and the dataset's own
// views. Pure math (no window), so it is unit-tested. Angles are in radians, lengths in
// world units; "up" is the scene's up direction (the dataset cameras' mean up, or +z).
#include <glm/glm.hpp>
#include <optional>

#include "splat/core/camera.hpp"

namespace splat::viewer {

class ViewController {
 public:
  // Looks at `target` from `distance` away, along the direction given by yaw (about `up`)
  // and pitch (above the horizontal), with a vertical field of view `fov_y`.
  ViewController(glm::vec3 target, float distance, glm::vec3 up, float fov_y = glm::radians(50.0f));

  // Mouse drags in pixels of a viewport `height` tall (a drag across the whole height turns
  // by π in orbit, moves the target by the visible height in pan).
  void orbit(float dx, float dy, float height);
  void pan(float dx, float dy, float height);
  // Scroll steps: positive moves closer (distance × 0.9 per step).
  void zoom(float steps);
  // Moves eye and target together along the view's axes: forward, right, up (world units).
  void fly(float forward, float right, float up);
  void reset();  // back to the starting view

  // Shows exactly `camera` (a dataset view, intrinsics and all) until the next move; the
  // orbit continues from it, about the point `distance` in front of it.
  void show_camera(const Camera& camera);

  // The camera for a viewport of width × height pixels: the dataset camera resized to it
  // when one is shown, else a pinhole with the controller's vertical field of view.
  Camera camera(int width, int height) const;

  glm::vec3 eye() const;
  glm::vec3 target() const { return target_; }
  float distance() const { return distance_; }

 private:
  glm::vec3 forward() const;  // unit, eye → target
  void leave_dataset_camera();

  glm::vec3 up_, target_;
  float distance_, yaw_ = 0, pitch_ = 0.3f, fov_y_;
  glm::vec3 start_target_;
  float start_distance_, start_yaw_, start_pitch_;
  glm::vec3 reference_x_, reference_y_;  // horizontal basis perpendicular to up
  std::optional<Camera> dataset_camera_;
};

// The point to frame and the distance to see it whole: the middle of the central 90 % of the
// means on each axis (outliers, e.g. floaters, ignored) and half that box's diagonal fitted
// into `fov_y`.
struct Framing {
  glm::vec3 center{0};
  float distance = 4;
};
Framing frame_points(const float* xyz, std::size_t count, float fov_y);

}  // namespace splat::viewer
