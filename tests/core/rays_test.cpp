// Camera rays agree with the rasterizer's projection; ray–box intersection cases.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "splat/core/rays.hpp"
#include "splat/raster/pixel_projection.hpp"
#include "splat/raster/projection_math.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

// A camera looking from an arbitrary direction, off-centre principal point, fx ≠ fy.
Camera tilted_camera() {
  Camera cam;
  cam.width = 120;
  cam.height = 90;
  cam.fx = 140.0f;
  cam.fy = 150.0f;
  cam.cx = 57.3f;
  cam.cy = 46.1f;
  cam.camera_from_world_rotation =
      quat_to_rotmat(Vec4<float>(0.8f, 0.3f, -0.4f, 0.2f));  // any rotation
  cam.camera_from_world_translation = glm::vec3(0.3f, -0.2f, 4.0f);
  return cam;
}

// Distance from p to the line through the ray.
float distance_to_ray(const Ray& ray, const glm::vec3& p) {
  const glm::vec3 d = p - ray.origin;
  return glm::length(d - glm::dot(d, ray.direction) * ray.direction);
}

TEST(NerfRay, PassesThroughThePointThatProjectsToItsPixel) {
  const Camera cam = tilted_camera();
  const glm::mat3 world_from_camera = glm::transpose(cam.camera_from_world_rotation);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-0.6f, 0.6f), z(1.0f, 8.0f);
  for (int i = 0; i < 200; ++i) {
    // A world point in front of the camera.
    const glm::vec3 camera_point(u(rng) * 3, u(rng) * 3, z(rng));
    const glm::vec3 world_point =
        world_from_camera * (camera_point - cam.camera_from_world_translation);
    // Where the rasterizer puts it (reference coordinates, pixel centres at integers).
    const Vec2<float> pixel = project_to_pixel(cam.camera_from_world(world_point), cam.fx,
                                               cam.fy, cam.cx, cam.cy);
    const Ray ray = camera_ray(cam, pixel.x, pixel.y);
    EXPECT_NEAR(glm::length(ray.direction), 1.0f, 1e-6f);
    EXPECT_GT(glm::dot(world_point - ray.origin, ray.direction), 0.0f);  // in front
    EXPECT_LT(distance_to_ray(ray, world_point), 2e-6f * glm::length(world_point - ray.origin));
  }
}

TEST(NerfRay, PixelCentreRayProjectsBackToThePixelCentre) {
  const Camera cam = tilted_camera();
  const PixelProjection project(cam);  // the rasterizer's own pixel arithmetic
  for (int y : {0, 17, 89})
    for (int x : {0, 60, 119}) {
      const Ray ray = camera_ray(cam, float(x), float(y));
      EXPECT_EQ(ray.origin, cam.center_in_world());
      const Vec2<float> pixel = project(ray.origin + 3.0f * ray.direction);
      EXPECT_NEAR(pixel.x, float(x), 2e-3f);
      EXPECT_NEAR(pixel.y, float(y), 2e-3f);
    }
}

TEST(NerfRay, CentreRayOfACameraLookingAtTheOriginPointsAtIt) {
  const Camera cam = test::looking_at_origin(64, 48, 3.0f);  // at z = −3, looking along +z
  // The image centre is between pixels 31 and 32 (reference coordinate 31.5).
  const Ray ray = camera_ray(cam, 31.5f, 23.5f);
  EXPECT_NEAR(ray.origin.z, -3.0f, 1e-6f);
  EXPECT_NEAR(ray.direction.x, 0.0f, 1e-7f);
  EXPECT_NEAR(ray.direction.y, 0.0f, 1e-7f);
  EXPECT_NEAR(ray.direction.z, 1.0f, 1e-7f);
  // y down: a pixel below the centre looks towards +y.
  EXPECT_GT(camera_ray(cam, 31.5f, 40.0f).direction.y, 0.0f);
}

TEST(NerfRay, CameraRaysCoverEveryPixelRowMajor) {
  const Camera cam = tilted_camera();
  std::vector<Ray> rays;
  camera_rays(cam, rays);
  ASSERT_EQ(rays.size(), std::size_t(cam.width * cam.height));
  const Ray expected = camera_ray(cam, 7.0f, 5.0f);
  EXPECT_EQ(rays[5 * cam.width + 7].direction, expected.direction);
}

const AxisAlignedBox kUnitBox{glm::vec3(-1.0f), glm::vec3(1.0f)};

TEST(NerfRay, BoxFromOutsideGivesEntryAndExit) {
  const Ray ray{glm::vec3(0.0f, 0.0f, -5.0f), glm::vec3(0.0f, 0.0f, 1.0f)};
  const auto bounds = intersect_box(ray, kUnitBox);
  ASSERT_TRUE(bounds.has_value());
  EXPECT_FLOAT_EQ(bounds->near, 4.0f);
  EXPECT_FLOAT_EQ(bounds->far, 6.0f);
  // A diagonal ray through the corner region.
  const Ray diagonal{glm::vec3(-3.0f, -3.0f, 0.5f), glm::normalize(glm::vec3(1.0f, 1.0f, 0.0f))};
  const auto diagonal_bounds = intersect_box(diagonal, kUnitBox);
  ASSERT_TRUE(diagonal_bounds.has_value());
  EXPECT_NEAR(diagonal_bounds->near, 2.0f * std::sqrt(2.0f), 1e-5f);
  EXPECT_NEAR(diagonal_bounds->far, 4.0f * std::sqrt(2.0f), 1e-5f);
}

TEST(NerfRay, BoxFromInsideStartsAtMinT) {
  const Ray ray{glm::vec3(0.5f, 0.0f, 0.0f), glm::vec3(1.0f, 0.0f, 0.0f)};
  const auto bounds = intersect_box(ray, kUnitBox);
  ASSERT_TRUE(bounds.has_value());
  EXPECT_FLOAT_EQ(bounds->near, 0.0f);
  EXPECT_FLOAT_EQ(bounds->far, 0.5f);
  const auto clipped = intersect_box(ray, kUnitBox, 0.1f);
  ASSERT_TRUE(clipped.has_value());
  EXPECT_FLOAT_EQ(clipped->near, 0.1f);
  EXPECT_FALSE(intersect_box(ray, kUnitBox, 0.6f).has_value());  // the box ends before min_t
}

TEST(NerfRay, BoxMissesGiveNoBounds) {
  // Passes beside the box.
  EXPECT_FALSE(intersect_box({glm::vec3(0.0f, 2.0f, -5.0f), glm::vec3(0.0f, 0.0f, 1.0f)},
                             kUnitBox).has_value());
  // The box is behind the origin.
  EXPECT_FALSE(intersect_box({glm::vec3(0.0f, 0.0f, 5.0f), glm::vec3(0.0f, 0.0f, 1.0f)},
                             kUnitBox).has_value());
  // Diagonal ray whose slabs overlap in no common t.
  EXPECT_FALSE(intersect_box({glm::vec3(-3.0f, 0.0f, 0.0f),
                              glm::normalize(glm::vec3(1.0f, 2.0f, 0.0f))}, kUnitBox)
                   .has_value());
}

TEST(NerfRay, AxisParallelRaysNeedNoDivisionByZero) {
  // Direction (1, 0, 0): y and z components are exactly zero.
  const glm::vec3 x_axis(1.0f, 0.0f, 0.0f);
  const auto inside_slab = intersect_box({glm::vec3(-4.0f, 0.3f, -0.7f), x_axis}, kUnitBox);
  ASSERT_TRUE(inside_slab.has_value());
  EXPECT_FLOAT_EQ(inside_slab->near, 3.0f);
  EXPECT_FLOAT_EQ(inside_slab->far, 5.0f);
  // Exactly on the box's face plane y = −1 (where (lo − o)·(1/0) would be NaN): inside.
  const auto on_face = intersect_box({glm::vec3(-4.0f, -1.0f, 0.0f), x_axis}, kUnitBox);
  ASSERT_TRUE(on_face.has_value());
  EXPECT_FLOAT_EQ(on_face->near, 3.0f);
  // Outside the y slab: never inside.
  EXPECT_FALSE(intersect_box({glm::vec3(-4.0f, 1.5f, 0.0f), x_axis}, kUnitBox).has_value());
  // Negative direction along an axis.
  const auto backwards =
      intersect_box({glm::vec3(0.0f, 0.0f, 3.0f), glm::vec3(0.0f, 0.0f, -1.0f)}, kUnitBox);
  ASSERT_TRUE(backwards.has_value());
  EXPECT_FLOAT_EQ(backwards->near, 2.0f);
  EXPECT_FLOAT_EQ(backwards->far, 4.0f);
}

}  // namespace
}  // namespace splat
