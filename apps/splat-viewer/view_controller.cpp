#include "apps/splat-viewer/view_controller.hpp"

#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>
#include <vector>

namespace splat::viewer {

namespace {
constexpr float kMaxPitch = 1.55f;  // just short of straight up or down, where yaw is undefined
constexpr float kMinDistance = 1e-3f;
}  // namespace

ViewController::ViewController(glm::vec3 target, float distance, glm::vec3 up, float fov_y)
    : up_(glm::normalize(up)), target_(target), distance_(std::max(distance, kMinDistance)), fov_y_(fov_y) {
  // Any horizontal axis will do as yaw 0; pick the world axis least aligned with up.
  const glm::vec3 a = std::abs(up_.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
  reference_x_ = glm::normalize(a - glm::dot(a, up_) * up_);
  reference_y_ = glm::cross(up_, reference_x_);
  start_target_ = target_;
  start_distance_ = distance_;
  start_yaw_ = yaw_;
  start_pitch_ = pitch_;
}

glm::vec3 ViewController::forward() const {
  // The eye sits at yaw/pitch on a sphere about the target; forward points back at it.
  const glm::vec3 horizontal = std::cos(yaw_) * reference_x_ + std::sin(yaw_) * reference_y_;
  const glm::vec3 eye_direction = std::cos(pitch_) * horizontal + std::sin(pitch_) * up_;
  return -eye_direction;
}

glm::vec3 ViewController::eye() const { return target_ - distance_ * forward(); }

void ViewController::leave_dataset_camera() { dataset_camera_.reset(); }

void ViewController::orbit(float dx, float dy, float height) {
  leave_dataset_camera();
  const float per_pixel = glm::pi<float>() / std::max(height, 1.0f);
  yaw_ -= dx * per_pixel;
  pitch_ = std::clamp(pitch_ + dy * per_pixel, -kMaxPitch, kMaxPitch);
}

void ViewController::pan(float dx, float dy, float height) {
  leave_dataset_camera();
  const glm::vec3 f = forward();
  const glm::vec3 right = glm::normalize(glm::cross(f, up_));
  const glm::vec3 camera_up = glm::cross(right, f);
  const float per_pixel = 2 * distance_ * std::tan(fov_y_ / 2) / std::max(height, 1.0f);
  target_ += (-dx * right + dy * camera_up) * per_pixel;
}

void ViewController::zoom(float steps) {
  leave_dataset_camera();
  distance_ = std::max(kMinDistance, distance_ * std::pow(0.9f, steps));
}

void ViewController::fly(float forward_amount, float right_amount, float up_amount) {
  leave_dataset_camera();
  const glm::vec3 f = forward();
  const glm::vec3 right = glm::normalize(glm::cross(f, up_));
  target_ += forward_amount * f + right_amount * right + up_amount * up_;
}

void ViewController::reset() {
  leave_dataset_camera();
  target_ = start_target_;
  distance_ = start_distance_;
  yaw_ = start_yaw_;
  pitch_ = start_pitch_;
}

void ViewController::show_camera(const Camera& camera) {
  dataset_camera_ = camera;
  // Continue from this view: keep the distance, put the target in front of the camera, and
  // read yaw and pitch off its viewing direction (OpenCV z is forward; row 2 of R).
  const glm::mat3& r = camera.camera_from_world_rotation;
  const glm::vec3 f = glm::normalize(glm::vec3(r[0][2], r[1][2], r[2][2]));
  target_ = camera.center_in_world() + distance_ * f;
  const glm::vec3 eye_direction = -f;
  pitch_ = std::clamp(std::asin(std::clamp(glm::dot(eye_direction, up_), -1.0f, 1.0f)), -kMaxPitch, kMaxPitch);
  yaw_ = std::atan2(glm::dot(eye_direction, reference_y_), glm::dot(eye_direction, reference_x_));
}

Camera ViewController::camera(int width, int height) const {
  if (dataset_camera_) return dataset_camera_->resized(width, height);
  const glm::vec3 f = forward();
  const glm::vec3 right = glm::normalize(glm::cross(f, up_));
  const glm::vec3 down = glm::cross(f, right);  // OpenCV: x right, y down, z forward
  Camera c;
  // Rows of R are the camera axes in world coordinates.
  glm::mat3 r;
  for (int col = 0; col < 3; ++col) {
    r[col][0] = right[col];
    r[col][1] = down[col];
    r[col][2] = f[col];
  }
  c.camera_from_world_rotation = r;
  c.camera_from_world_translation = -(r * eye());
  c.width = width;
  c.height = height;
  c.fy = 0.5f * float(height) / std::tan(fov_y_ / 2);
  c.fx = c.fy;
  c.cx = 0.5f * float(width);
  c.cy = 0.5f * float(height);
  return c;
}

Framing frame_points(const float* xyz, std::size_t count, float fov_y) {
  Framing framing;
  if (count == 0) return framing;
  glm::vec3 low, high;
  std::vector<float> axis(count);
  for (int k = 0; k < 3; ++k) {
    for (std::size_t i = 0; i < count; ++i) axis[i] = xyz[3 * i + k];
    const std::size_t lo = count / 20, hi = count - 1 - count / 20;
    std::nth_element(axis.begin(), axis.begin() + std::ptrdiff_t(lo), axis.end());
    low[k] = axis[lo];
    std::nth_element(axis.begin(), axis.begin() + std::ptrdiff_t(hi), axis.end());
    high[k] = axis[hi];
  }
  framing.center = 0.5f * (low + high);
  const float radius = std::max(0.5f * glm::length(high - low), 1e-3f);
  framing.distance = 1.1f * radius / std::sin(fov_y / 2);
  return framing;
}

}  // namespace splat::viewer
