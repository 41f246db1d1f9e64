#include "splat/core/rays.hpp"

#include <algorithm>
#include <cstddef>
#include <limits>

namespace splat {

Ray camera_ray(const Camera& camera, float px, float py) {
  // Reference coordinate u is image-plane coordinate u + 0.5 (see rays.hpp); the image-plane
  // point (x_img, y_img) at depth z = 1 is ((x_img − cx)/fx, (y_img − cy)/fy, 1) in camera
  // axes. World direction = Rᵀ · camera direction (R is orthonormal), origin = −Rᵀ t.
  const glm::vec3 direction_camera((px + 0.5f - camera.cx) / camera.fx,
                                   (py + 0.5f - camera.cy) / camera.fy, 1.0f);
  const glm::mat3 world_from_camera_rotation = glm::transpose(camera.camera_from_world_rotation);
  return {camera.center_in_world(),
          glm::normalize(world_from_camera_rotation * direction_camera)};
}

void camera_rays(const Camera& camera, std::vector<Ray>& rays) {
  rays.resize(std::size_t(camera.width) * std::size_t(camera.height));
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x)
      rays[std::size_t(y) * camera.width + x] = camera_ray(camera, float(x), float(y));
}

std::optional<RayBounds> intersect_box(const Ray& ray, const AxisAlignedBox& box, float min_t) {
  // Slab method: per axis the ray is between the two planes for t in [t_lo, t_hi]; the box
  // interval is the intersection of the three.
  float enter = min_t;
  float exit = std::numeric_limits<float>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    const float o = ray.origin[axis], d = ray.direction[axis];
    if (d == 0.0f) {
      // Parallel to this slab: 1/d would be ±inf and (lo − o)·inf is NaN when o == lo.
      if (o < box.lo[axis] || o > box.hi[axis]) return std::nullopt;
      continue;
    }
    const float inv_d = 1.0f / d;
    float t0 = (box.lo[axis] - o) * inv_d, t1 = (box.hi[axis] - o) * inv_d;
    if (t0 > t1) std::swap(t0, t1);
    enter = std::max(enter, t0);
    exit = std::min(exit, t1);
  }
  if (!(enter < exit)) return std::nullopt;
  return RayBounds{enter, exit};
}

}  // namespace splat
