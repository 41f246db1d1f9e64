#include "splat/gaussians/view_points.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "splat/core/camera_rig.hpp"
#include "splat/core/error.hpp"
#include "splat/core/random.hpp"
#include "splat/core/rays.hpp"

namespace splat {
namespace {

// Colours that differ by this much (mean over the channels) no longer count as the same
// surface seen twice: about 25 of 255 levels, room for shading that changes with the view
// and for the pixel grid (the nearest pixel is read, not an interpolation).
constexpr float kColourTolerance = 0.1f;

void check_views(std::span<const DatasetView> views, const char* who) {
  if (views.empty()) throw ArgumentError(std::string(who) + ": no views to place points by");
}

// The colour of the pixel holding image-plane position (u, v) (pixel i covers [i, i + 1]).
glm::vec3 pixel_colour(const Image& image, float u, float v) {
  const int x = std::clamp(int(u), 0, image.width - 1), y = std::clamp(int(v), 0, image.height - 1);
  const float* p = &image.data[(std::size_t(y) * image.width + x) * image.channels];
  return {p[0], p[1], p[2]};
}

void append(PointCloud& cloud, const glm::vec3& position, const glm::vec3& colour) {
  for (int a = 0; a < 3; ++a) {
    cloud.positions.push_back(position[a]);
    cloud.colors.push_back(colour[a]);
  }
}

// Direction i of n spread evenly over the unit sphere (the Fibonacci lattice: equal-area
// bands in y, successive points turned by the golden angle).
glm::vec3 fibonacci_direction(std::size_t i, std::size_t n) {
  const double golden_angle = std::numbers::pi * (3.0 - std::sqrt(5.0));
  const double y = 1.0 - 2.0 * (double(i) + 0.5) / double(n);
  const double r = std::sqrt(std::max(0.0, 1.0 - y * y));
  const double phi = golden_angle * double(i);
  return glm::vec3(float(r * std::cos(phi)), float(y), float(r * std::sin(phi)));
}

// The lattice points on the sphere that some view sees, with their mean pixel colour.
PointCloud seen_lattice(std::span<const DatasetView> views, const glm::vec3& centre, float radius,
                        std::size_t lattice) {
  PointCloud cloud;
  for (std::size_t i = 0; i < lattice; ++i) {
    const glm::vec3 p = centre + radius * fibonacci_direction(i, lattice);
    glm::vec3 sum(0.0f);
    int seen = 0;
    for (const DatasetView& view : views) {
      if (!in_view(view.camera, p)) continue;
      const glm::vec3 c = view.camera.camera_from_world(p);
      sum += pixel_colour(view.image, view.camera.fx * c.x / c.z + view.camera.cx,
                          view.camera.fy * c.y / c.z + view.camera.cy);
      ++seen;
    }
    if (seen > 0) append(cloud, p, sum / float(seen));
  }
  return cloud;
}

// How strongly the views other than `source` that see `p` agree that it has `colour`: per
// view 1 − (mean absolute channel difference) / kColourTolerance, at least 0, summed.
float colour_votes(std::span<const DatasetView> views, std::size_t source, const glm::vec3& p,
                   const glm::vec3& colour) {
  float votes = 0;
  for (std::size_t o = 0; o < views.size(); ++o) {
    const Camera& camera = views[o].camera;
    if (o == source || !in_view(camera, p)) continue;
    const glm::vec3 c = camera.camera_from_world(p);
    const glm::vec3 seen = pixel_colour(views[o].image, camera.fx * c.x / c.z + camera.cx, camera.fy * c.y / c.z + camera.cy);
    const glm::vec3 d = glm::abs(seen - colour);
    votes += std::max(0.0f, 1.0f - (d.x + d.y + d.z) / (3.0f * kColourTolerance));
  }
  return votes;
}

}  // namespace

PointCloud frustum_points(std::span<const DatasetView> views, std::size_t count, float near, float far,
                          int depth_candidates, std::mt19937& rng) {
  check_views(views, "frustum_points");
  if (depth_candidates < 1)
    throw ArgumentError("frustum_points: " + std::to_string(depth_candidates) + " depth candidates (at least 1)");
  if (!(near > 0.0f && near < far && std::isfinite(far)))
    throw ArgumentError("frustum_points: needs 0 < near < far, not near " + std::to_string(near) + ", far " +
                        std::to_string(far));
  PointCloud cloud;
  cloud.positions.reserve(3 * count);
  cloud.colors.reserve(3 * count);
  const float near_disparity = 1.0f / near, far_disparity = 1.0f / far;
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t v = std::min(views.size() - 1, std::size_t(uniform01(rng) * float(views.size())));
    const DatasetView& view = views[v];
    const float u = uniform01(rng) * float(view.camera.width), w = uniform01(rng) * float(view.camera.height);
    // camera_ray takes reference coordinates, pixel centres at integers: image-plane u − 0.5.
    const Ray ray = camera_ray(view.camera, u - 0.5f, w - 0.5f);
    const glm::vec3 colour = pixel_colour(view.image, u, w);
    glm::vec3 best(0.0f);
    float best_votes = -1;
    for (int k = 0; k < depth_candidates; ++k) {
      const float disparity = far_disparity + uniform01(rng) * (near_disparity - far_disparity);
      const glm::vec3 p = ray.origin + ray.direction / disparity;
      const float votes = depth_candidates > 1 ? colour_votes(views, v, p, colour) : 0.0f;
      if (votes > best_votes) best_votes = votes, best = p;  // ties: the earlier draw
    }
    append(cloud, best, colour);
  }
  return cloud;
}

PointCloud background_shell(std::span<const DatasetView> views, const glm::vec3& centre, float radius,
                            std::size_t count) {
  check_views(views, "background_shell");
  if (count == 0) throw ArgumentError("background_shell: zero points requested");
  if (!(radius > 0.0f && std::isfinite(radius)))
    throw ArgumentError("background_shell: radius " + std::to_string(radius) + " is not positive and finite");
  // First the whole sphere at `count` points, to measure the share the views see; then a
  // lattice dense enough that the seen part holds about `count`.
  const PointCloud trial = seen_lattice(views, centre, radius, count);
  if (trial.size() == 0) return trial;
  const std::size_t lattice = std::size_t(std::ceil(double(count) * double(count) / double(trial.size())));
  return seen_lattice(views, centre, radius, lattice);
}

}  // namespace splat
