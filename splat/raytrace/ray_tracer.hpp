#pragma once
// Closest-hit and shadow queries against a mesh, through Embree 3. The Embree device and
// scene are owned here (RAII), so nothing outside this file sees Embree's C API.
#include <cstdint>
#include <memory>

#include <glm/glm.hpp>

#include "splat/raytrace/gltf_mesh.hpp"

namespace splat::raytrace {

struct RayHit {
  float t = 0;                   // distance along the (unit) direction
  std::uint32_t triangle = 0;    // index into Mesh::triangle_material
  float u = 0, v = 0;            // barycentrics: p = (1-u-v)·p0 + u·p1 + v·p2
};

class RayTracer {
 public:
  // Builds the acceleration structure over `mesh`'s triangles (copied into Embree buffers).
  explicit RayTracer(const Mesh& mesh);
  ~RayTracer();
  RayTracer(const RayTracer&) = delete;
  RayTracer& operator=(const RayTracer&) = delete;

  // First hit of the ray origin + t·direction with t in [t_near, t_far]; `direction` must be
  // unit length. Safe to call from many threads at once.
  bool intersect(const glm::vec3& origin, const glm::vec3& direction, RayHit& hit,
                 float t_near = 0.0f, float t_far = 1e30f) const;
  // Whether anything lies on the segment (t_near, t_far) of the ray: shadow rays.
  bool occluded(const glm::vec3& origin, const glm::vec3& direction, float t_near,
                float t_far) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace splat::raytrace
