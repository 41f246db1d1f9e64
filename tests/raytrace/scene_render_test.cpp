// Rendered depth against analytic depth for a plane and a sphere, and renders identical for
// any thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <tbb/global_control.h>

#include "tests/cli_support.hpp"
#include "splat/raytrace/gltf_mesh.hpp"
#include "splat/raytrace/orbit_rig.hpp"
#include "splat/raytrace/scene_renderer.hpp"
#include "tests/raytrace/scene_test_files.hpp"
#include "splat/data/image_io.hpp"
#include "tests/test_support.hpp"

namespace splat::raytrace {
namespace {

// The pixel centre's ray in world coordinates, unnormalised, with camera z = 1: the t at
// which it meets a surface is that surface's camera depth.
glm::vec3 centre_ray(const Camera& cam, int x, int y) {
  const glm::vec3 d_cam((x + 0.5f - cam.cx) / cam.fx, (y + 0.5f - cam.cy) / cam.fy, 1.0f);
  return glm::transpose(cam.camera_from_world_rotation) * d_cam;
}

OrbitSpec small_orbit(int width, int height) {
  OrbitSpec o;
  o.radius = 4.0f;
  o.elevation_lo_deg = 20;
  o.elevation_hi_deg = 50;
  o.fov_x_deg = 50;
  o.width = width;
  o.height = height;
  o.train = 2;
  o.test = 0;
  return o;
}

const Lighting kLighting{{LightSpec{}}, glm::vec3(0.2f)};

TEST(SceneRender, PlaneDepthMatchesTheAnalyticDepth) {
  const auto dir = test::scratch_dir("scene_plane_depth");
  test::write_test_gltf(dir / "plane.gltf", test::plane_mesh(50.0f, -0.25f));
  const Mesh mesh = load_gltf_mesh(dir / "plane.gltf");
  const RayTracer tracer(mesh);
  for (const Camera& cam : orbit_rig_cameras(small_orbit(20, 14), Split::train)) {
    const RenderedView view = render_view(mesh, tracer, kLighting, cam, RenderSettings{2, 0, {}}, 0);
    const glm::vec3 c = cam.center_in_world();
    for (int y = 0; y < cam.height; ++y)
      for (int x = 0; x < cam.width; ++x) {
        const glm::vec3 d = centre_ray(cam, x, y);
        const float t = (-0.25f - c.y) / d.y;  // every pixel looks down onto the plane here
        ASSERT_GT(t, 0.0f);
        EXPECT_NEAR(view.depth.at(x, y, 0), t, 1e-4f * t) << x << "," << y;
        EXPECT_EQ(view.color.at(x, y, 3), 1.0f);  // fully covered
      }
  }
}

TEST(SceneRender, SphereDepthMatchesTheAnalyticDepth) {
  const auto dir = test::scratch_dir("scene_sphere_depth");
  test::write_test_gltf(dir / "sphere.gltf", test::sphere_mesh(1.0f, 48, 96));
  const Mesh mesh = load_gltf_mesh(dir / "sphere.gltf");
  const RayTracer tracer(mesh);
  const Camera cam = orbit_rig_cameras(small_orbit(32, 32), Split::train)[0];
  const RenderedView view = render_view(mesh, tracer, kLighting, cam, RenderSettings{4, 0, {}}, 0);
  const glm::vec3 c = cam.center_in_world();
  int compared = 0, coverage_mismatch = 0;
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      const glm::vec3 d = centre_ray(cam, x, y);
      // |c + t d|² = 1 → (d·d) t² + 2 (c·d) t + (c·c − 1) = 0, nearer root.
      const float a = glm::dot(d, d), b = glm::dot(c, d), k = glm::dot(c, c) - 1.0f;
      const float disc = b * b - a * k;
      const bool analytic_hit = disc > 0;
      const bool rendered_hit = view.depth.at(x, y, 0) > 0;
      if (analytic_hit != rendered_hit) {
        ++coverage_mismatch;  // only where the ray grazes the silhouette
        continue;
      }
      // Coverage: whole pixels (footprint about 0.12 here) clear of the silhouette are
      // fully in or fully out; |c|² − (c·d)²/|d|² is the ray's squared distance to the centre.
      const float miss_distance = std::sqrt(std::max(0.0f, glm::dot(c, c) - b * b / a));
      if (miss_distance > 1.2f) {
        EXPECT_EQ(view.color.at(x, y, 3), 0.0f) << x << "," << y;
      }
      if (miss_distance < 0.8f) {
        EXPECT_EQ(view.color.at(x, y, 3), 1.0f) << x << "," << y;
      }
      if (!analytic_hit) continue;
      const float t = (-b - std::sqrt(disc)) / a;
      // The tessellation lies inside the sphere by at most 1 − cos(π/48) ≈ 0.002 (radius 1).
      EXPECT_NEAR(view.depth.at(x, y, 0), t, 0.01f) << x << "," << y;
      ++compared;
    }
  EXPECT_GT(compared, 100);
  EXPECT_LE(coverage_mismatch, 4);
}

TEST(SceneRender, PngBytesAreIdenticalForOneAndTwoThreads) {
  const auto dir = test::scratch_dir("scene_threads");
  test::write_test_gltf(dir / "sphere.gltf", test::sphere_mesh(1.0f, 12, 24));
  const Mesh mesh = load_gltf_mesh(dir / "sphere.gltf");
  const RayTracer tracer(mesh);
  const Camera cam = orbit_rig_cameras(small_orbit(40, 40), Split::train)[1];
  for (int threads : {1, 2}) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    const RenderedView view = render_view(mesh, tracer, kLighting, cam, RenderSettings{8, 7, {}}, 3);
    std::string name = "t";  // two steps: GCC 12 warns falsely (-Wrestrict) on "lit" + string
    name += std::to_string(threads) + ".png";
    write_png(view.color, dir / name, 8);
  }
  const std::string one = test::read_file(dir / "t1.png"), two = test::read_file(dir / "t2.png");
  EXPECT_FALSE(one.empty());
  EXPECT_EQ(one, two);
}

}  // namespace
}  // namespace splat::raytrace
