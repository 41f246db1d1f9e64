// Shading against hand-computed values: Lambert + GGX under a light straight overhead,
// shadows, point-light falloff, metallic tinting, and background compositing.
#include <gtest/gtest.h>

#include <numbers>

#include "splat/raytrace/orbit_rig.hpp"
#include "splat/raytrace/scene_renderer.hpp"
#include "splat/raytrace/shading.hpp"

namespace splat::raytrace {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

// A floor (y = 0, 40 × 40) and a small square roof at y = 1 over [-0.5, 0.5]² in x and z.
Mesh floor_and_roof(const Material& floor_material) {
  Mesh m;
  auto quad = [&](float half, float y, int material) {
    const std::uint32_t base = std::uint32_t(m.positions.size());
    for (glm::vec2 c : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)}) {
      m.positions.emplace_back(half * c.x, y, half * c.y);
      m.normals.emplace_back(0, 1, 0);
      m.uvs.emplace_back(0.0f);
    }
    m.indices.insert(m.indices.end(), {base, base + 2, base + 1, base, base + 3, base + 2});
    m.triangle_material.insert(m.triangle_material.end(), 2, material);
  };
  quad(20.0f, 0.0f, 0);
  quad(0.5f, 1.0f, 1);
  m.materials = {floor_material, Material{}};
  return m;
}

glm::vec3 shade_straight_down(const Mesh& mesh, const Lighting& lighting, glm::vec3 from) {
  const RayTracer tracer(mesh);
  RayHit hit;
  const glm::vec3 down(0, -1, 0);
  EXPECT_TRUE(tracer.intersect(from, down, hit));
  return shade(mesh, tracer, lighting, hit, from, down);
}

TEST(SceneShading, DiffuseAndSpecularUnderAnOverheadLight) {
  Material grey;
  grey.base_color = glm::vec4(0.5f, 0.5f, 0.5f, 1.0f);
  grey.metallic = 0.0f;
  grey.roughness = 1.0f;
  const Mesh mesh = floor_and_roof(grey);
  LightSpec sun;  // travelling straight down
  sun.intensity = 2.0f;
  const Lighting lighting{{sun}, glm::vec3(0.1f)};
  // Viewed and lit along the normal, α = 1: D = 1/π, Smith–Schlick visibility 1, F = 0.04,
  // so the specular term is 0.04 / (4π); diffuse is 0.5 / π.
  const float lit = 0.1f * 0.5f + 2.0f * (0.5f / kPi + 0.01f / kPi);
  const glm::vec3 sunny = shade_straight_down(mesh, lighting, {3, 5, 0.25f});
  EXPECT_NEAR(sunny.r, lit, 1e-4f);
  EXPECT_NEAR(sunny.b, lit, 1e-4f);
  // Under the roof only the ambient term remains.
  const glm::vec3 shadowed = shade_straight_down(mesh, lighting, {0.1f, 0.5f, 0.2f});
  EXPECT_NEAR(shadowed.g, 0.1f * 0.5f, 1e-6f);
}

TEST(SceneShading, PointLightsFallOffWithTheSquaredDistance) {
  Material grey;
  grey.base_color = glm::vec4(0.5f);
  grey.metallic = 0.0f;
  const Mesh mesh = floor_and_roof(grey);
  LightSpec bulb;
  bulb.type = LightSpec::Type::point;
  bulb.position = {3, 2, 0};
  bulb.intensity = 8.0f;  // 8 / 2² = 2 at the floor below it
  const glm::vec3 near = shade_straight_down(mesh, Lighting{{bulb}, glm::vec3(0.0f)}, {3, 1, 0});
  EXPECT_NEAR(near.r, 2.0f * (0.5f / kPi + 0.01f / kPi), 1e-4f);
}

TEST(SceneShading, MetalsTintTheirSpecularAndHaveNoDiffuse) {
  Material red_metal;
  red_metal.base_color = glm::vec4(1, 0, 0, 1);
  red_metal.metallic = 1.0f;
  red_metal.roughness = 0.5f;
  const Mesh mesh = floor_and_roof(red_metal);
  LightSpec sun;
  const glm::vec3 c = shade_straight_down(mesh, Lighting{{sun}, glm::vec3(0.0f)}, {3, 5, 0});
  EXPECT_GT(c.r, 0.1f);
  EXPECT_EQ(c.g, 0.0f);
  EXPECT_EQ(c.b, 0.0f);
}

TEST(SceneShading, BackgroundIsCompositedLikeDatasetsDo) {
  const Mesh mesh = floor_and_roof(Material{});
  const RayTracer tracer(mesh);
  OrbitSpec orbit;
  orbit.width = 24;
  orbit.height = 20;
  orbit.elevation_lo_deg = orbit.elevation_hi_deg = 5;  // the horizon is in view
  orbit.train = 1;
  const Camera cam = orbit_rig_cameras(orbit, Split::train)[0];
  const Lighting lighting{{LightSpec{}}, glm::vec3(0.2f)};
  const RenderedView clear = render_view(mesh, tracer, lighting, cam, RenderSettings{4, 1, {}}, 0);
  const glm::vec3 bg(0.2f, 0.6f, 1.0f);
  const RenderedView opaque = render_view(mesh, tracer, lighting, cam, RenderSettings{4, 1, bg}, 0);
  const float bg_array[3] = {bg.r, bg.g, bg.b};
  const Image expected = composite_onto(clear.color, bg_array);
  int partial = 0;
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      const float a = clear.color.at(x, y, 3);
      partial += a > 0 && a < 1;
      EXPECT_EQ(opaque.color.at(x, y, 3), 1.0f);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(opaque.color.at(x, y, c), expected.at(x, y, c), 1e-6f);
    }
  EXPECT_GT(partial, 0);  // the floor's far edge is anti-aliased
}

}  // namespace
}  // namespace splat::raytrace
