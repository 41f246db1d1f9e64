// Embree queries against a known mesh: distances and shadow tests.
#include <gtest/gtest.h>

#include "splat/raytrace/ray_tracer.hpp"

namespace splat::raytrace {
namespace {

// The unit cube [-0.5, 0.5]^3 as a Mesh built in memory (12 triangles).
Mesh unit_cube() {
  Mesh m;
  for (int i = 0; i < 8; ++i) {
    m.positions.emplace_back(i & 1 ? 0.5f : -0.5f, i & 2 ? 0.5f : -0.5f, i & 4 ? 0.5f : -0.5f);
    m.normals.push_back(glm::normalize(m.positions.back()));
    m.uvs.emplace_back(0.0f);
  }
  m.indices = {0, 1, 3, 0, 3, 2, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
               2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 3, 7, 1, 7, 5};
  m.triangle_material.assign(12, 0);
  m.materials.push_back(Material{});
  return m;
}

TEST(SceneRayTracer, HitsTheUnitCubeAtTheRightDistance) {
  const Mesh cube = unit_cube();
  const RayTracer tracer(cube);
  RayHit hit;
  ASSERT_TRUE(tracer.intersect({0.1f, 0.2f, -5.0f}, {0, 0, 1}, hit));
  EXPECT_NEAR(hit.t, 4.5f, 1e-5f);
  ASSERT_TRUE(tracer.intersect({3.0f, -0.3f, 0.1f}, {-1, 0, 0}, hit));
  EXPECT_NEAR(hit.t, 2.5f, 1e-5f);
  // Diagonal: from (2, 2, 2) towards the centre enters at the corner (0.5, 0.5, 0.5).
  const glm::vec3 d = glm::normalize(glm::vec3(-1.0f));
  ASSERT_TRUE(tracer.intersect({2, 2, 2}, d, hit));
  EXPECT_NEAR(hit.t, std::sqrt(3.0f) * 1.5f, 1e-4f);
  // The hit point recovered from the barycentrics lies on the cube's surface.
  const std::uint32_t* tri = &cube.indices[3 * hit.triangle];
  const glm::vec3 p = (1 - hit.u - hit.v) * cube.positions[tri[0]] + hit.u * cube.positions[tri[1]] +
                      hit.v * cube.positions[tri[2]];
  EXPECT_NEAR(glm::length(p - glm::vec3(0.5f)), 0.0f, 1e-4f);

  EXPECT_FALSE(tracer.intersect({0.0f, 2.0f, -5.0f}, {0, 0, 1}, hit));  // passes above
  EXPECT_FALSE(tracer.intersect({0.0f, 0.0f, -5.0f}, {0, 0, 1}, hit, 0.0f, 4.0f));  // too short
  EXPECT_TRUE(tracer.occluded({0.0f, 0.0f, -5.0f}, {0, 0, 1}, 0.0f, 10.0f));
  EXPECT_FALSE(tracer.occluded({0.0f, 0.0f, -5.0f}, {0, 0, 1}, 0.0f, 4.0f));
}

}  // namespace
}  // namespace splat::raytrace
