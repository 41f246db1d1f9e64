#include "splat/nerf/scene_space.hpp"

#include <algorithm>
#include <cmath>

#include "splat/core/error.hpp"
#include "splat/core/random.hpp"
#include "splat/nerf/samplers.hpp"

namespace splat {

glm::vec3 SceneSpace::to_network(const glm::vec3& world) const {
  if (!unbounded) return world;
  const glm::vec3 centre = 0.5f * (box.lo + box.hi), half = 0.5f * (box.hi - box.lo);
  const glm::vec3 u = (world - centre) / half;
  const float norm = std::max({std::abs(u.x), std::abs(u.y), std::abs(u.z)});
  if (norm <= 1.0f) return u;
  return (2.0f - 1.0f / norm) * (u / norm);
}

AxisAlignedBox SceneSpace::network_box() const {
  if (!unbounded) return box;
  return {glm::vec3(-2.0f), glm::vec3(2.0f)};
}

bool SceneSpace::place_samples(const Ray& ray, float near, bool jitter, std::mt19937& rng, std::span<float> t,
                               std::span<float> delta) const {
  if (t.size() != delta.size()) throw ArgumentError("place_samples: t and delta differ in size");
  const std::optional<RayBounds> inside = intersect_box(ray, box, near);
  if (!unbounded) {
    if (!inside) return false;
    stratified_samples(*inside, jitter, rng, t, delta);
    return true;
  }
  const glm::vec3 half = 0.5f * (box.hi - box.lo);
  const float size = std::max({half.x, half.y, half.z});
  // Evenly in distance to where the ray leaves the box (none if it misses it), then evenly
  // in disparity to the far distance.
  const float exit = inside ? std::max(inside->far, near) : near;
  const float far = std::max(kUnboundedFarFactor * size, 2.0f * exit);
  const std::size_t n = t.size(), n_near = inside && exit > near ? n / 2 : 0, n_far = n - n_near;
  if (n_near > 0)
    stratified_samples({near, exit}, jitter, rng, t.first(n_near), delta.first(n_near));
  const float first_disparity = 1.0f / std::max(exit, 1e-6f * size), last_disparity = 1.0f / far;
  for (std::size_t i = 0; i < n_far; ++i) {
    const float s = (float(i) + (jitter ? uniform01(rng) : 0.5f)) / float(n_far);
    t[n_near + i] = std::min(far, 1.0f / (first_disparity + s * (last_disparity - first_disparity)));
  }
  for (std::size_t i = 0; i + 1 < n; ++i) delta[i] = t[i + 1] - t[i];
  if (n > 0) delta[n - 1] = std::max(0.0f, far - t[n - 1]);
  return true;
}

}  // namespace splat
