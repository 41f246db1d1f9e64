#include "splat/data/camera_paths.hpp"

#include <algorithm>
#include <cmath>

#include <glm/gtc/quaternion.hpp>

#include "splat/core/error.hpp"
#include "splat/data/orbit_cameras.hpp"

namespace splat {
namespace {

constexpr float kTwoPi = 6.28318530717958647f;

void check_path_size(int frames, int width, int height) {
  if (frames < 1) throw ArgumentError("a camera path needs at least one frame");
  if (width < 1 || height < 1) throw ArgumentError("a camera path needs a positive image size");
}

// One turn round the framing's circle, frame i at elevation elevation_at(i).
template <class Elevation>
std::vector<Camera> circling_path(const PathFraming& f, int frames, int width, int height,
                                  Elevation elevation_at) {
  check_path_size(frames, width, height);
  const glm::vec3 up = glm::normalize(f.up);
  const glm::vec3 side = glm::normalize(f.start - glm::dot(f.start, up) * up);
  const glm::vec3 across = glm::cross(up, side);  // a quarter turn on, counter-clockwise about up
  const float focal = 0.5f * float(height) / std::tan(0.5f * f.fov_y);
  std::vector<Camera> cameras;
  cameras.reserve(std::size_t(frames));
  for (int i = 0; i < frames; ++i) {
    const float azimuth = kTwoPi * float(i) / float(frames);
    const float elevation = std::clamp(elevation_at(i), -kMaxPathElevation, kMaxPathElevation);
    const glm::vec3 direction = std::cos(elevation) * (std::cos(azimuth) * side + std::sin(azimuth) * across) +
                                std::sin(elevation) * up;
    cameras.push_back(look_at(f.center + f.distance * direction, f.center, up, focal, focal, width, height));
  }
  return cameras;
}

// Uniform Catmull–Rom between p1 (u = 0) and p2 (u = 1), p0 and p3 their outer neighbours.
glm::vec3 catmull_rom(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2, const glm::vec3& p3,
                      float u) {
  const float u2 = u * u, u3 = u2 * u;
  return 0.5f * (2.0f * p1 + (p2 - p0) * u + (2.0f * p0 - 5.0f * p1 + 4.0f * p2 - p3) * u2 +
                 (3.0f * p1 - p0 - 3.0f * p2 + p3) * u3);
}

float mix(float a, float b, float u) { return a + (b - a) * u; }

}  // namespace

std::vector<Camera> orbit_path(const PathFraming& framing, int frames, int width, int height) {
  return circling_path(framing, frames, width, height, [&](int) { return framing.elevation; });
}

std::vector<Camera> spiral_path(const PathFraming& framing, int frames, int width, int height) {
  return circling_path(framing, frames, width, height, [&](int i) {
    return framing.elevation + kSpiralElevationSwing * std::sin(kTwoPi * float(i) / float(frames));
  });
}

std::vector<Camera> interpolated_path(std::span<const Camera> views, int frames, int width, int height) {
  check_path_size(frames, width, height);
  if (views.empty()) throw ArgumentError("interpolating a camera path needs at least one view");
  std::vector<Camera> keys;
  for (const Camera& view : views) keys.push_back(view.resized(width, height));
  const long long segments = (long long)(keys.size()) - 1;
  const auto key = [&](long long k) -> const Camera& { return keys[std::size_t(std::clamp(k, 0LL, segments))]; };
  std::vector<Camera> path;
  path.reserve(std::size_t(frames));
  for (int i = 0; i < frames; ++i) {
    // Frame i sits at i·segments/(frames − 1) along the views; in integers, so a frame that
    // lands on a view is that view exactly.
    const long long scaled = frames > 1 ? (long long)(i) * segments : 0;
    const long long span = std::max(frames - 1, 1);
    const long long k = scaled / span, remainder = scaled % span;
    if (remainder == 0) {
      path.push_back(key(k));
      continue;
    }
    const float u = float(remainder) / float(span);
    const Camera &a = key(k), &b = key(k + 1);
    const glm::vec3 center = catmull_rom(key(k - 1).center_in_world(), a.center_in_world(),
                                         b.center_in_world(), key(k + 2).center_in_world(), u);
    glm::quat qa = glm::quat_cast(a.camera_from_world_rotation), qb = glm::quat_cast(b.camera_from_world_rotation);
    if (glm::dot(qa, qb) < 0.0f) qb = -qb;  // the shorter way round
    Camera c = a;
    c.camera_from_world_rotation = glm::mat3_cast(glm::normalize(glm::slerp(qa, qb, u)));
    c.camera_from_world_translation = -(c.camera_from_world_rotation * center);
    c.fx = mix(a.fx, b.fx, u);
    c.fy = mix(a.fy, b.fy, u);
    c.cx = mix(a.cx, b.cx, u);
    c.cy = mix(a.cy, b.cy, u);
    path.push_back(c);
  }
  return path;
}

}  // namespace splat
