#pragma once
// Camera rays for the NeRF, and where they cross the scene's bounding box.
//
// Pixel convention: the same pixel as the rasterizer. The rasterizer evaluates pixel (i, j)
// at its centre, the point (i + 0.5, j + 0.5) of the camera's image plane (camera.hpp:
// pixel i covers [i, i + 1]), which is coordinate (i, j) in the reference rasterizer's
// pixel-centres-at-integers convention (projection_math.hpp: u = fx·x/z + cx − 0.5). So
// camera_ray(camera, u, v) takes that reference coordinate: for integer (u, v) it is the
// ray through the centre of pixel (u, v), and a world point that project_to_pixel sends to
// (u, v) lies on camera_ray(camera, u, v). Fractional values give rays inside the pixel.
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "splat/core/camera.hpp"

namespace splat {

// A ray in world space: points origin + t·direction, t ≥ 0; direction has unit length, so t
// is the distance from the origin (and NeRF depths are distances, not camera z).
struct Ray {
  glm::vec3 origin;
  glm::vec3 direction;
};

// The ray from the camera centre through pixel coordinate (px, py), pixel centres at
// integers (see above).
Ray camera_ray(const Camera& camera, float px, float py);

// Every pixel's centre ray, row-major ([height · width]); `rays` is resized (no allocation
// when it already has the size).
void camera_rays(const Camera& camera, std::vector<Ray>& rays);

// The interval of t a ray spends in the scene: samples go in [near, far].
struct RayBounds {
  float near;
  float far;
};

// Axis-aligned box [lo, hi] (world space), the scene's bounds.
struct AxisAlignedBox {
  glm::vec3 lo;
  glm::vec3 hi;
  bool contains(const glm::vec3& p) const {
    return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z;
  }
};

// Where the ray is inside `box`, clipped to t ≥ min_t (the part behind the origin, or closer
// than a near plane, is not sampled): [max(entry, min_t), exit]. Empty (std::nullopt) when
// the ray misses the box, only touches it (entry == exit), or the box lies entirely before
// min_t; rays without bounds get no samples. A ray starting inside the box gets near = min_t.
// Direction components that are exactly zero (axis-parallel rays) are handled without
// dividing by zero: the ray is then inside that slab for all t or for none.
std::optional<RayBounds> intersect_box(const Ray& ray, const AxisAlignedBox& box,
                                       float min_t = 0.0f);

}  // namespace splat
