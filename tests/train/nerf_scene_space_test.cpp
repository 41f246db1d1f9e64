// Where the NeRF samples follows the data: the point cloud's box, the cube an object rig
// sees, or an unbounded space round cameras whose images show a background.
#include "splat/train/nerf_scene_space.hpp"

#include <gtest/gtest.h>

#include "splat/core/camera_rig.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

using test::orbit_dataset;

const AxisAlignedBox kFallback{glm::vec3(-1.5f), glm::vec3(1.5f)};

void expect_cube(const AxisAlignedBox& box, const glm::vec3& centre, float half) {
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(box.lo[a], centre[a] - half, 1e-3f * half) << a;
    EXPECT_NEAR(box.hi[a], centre[a] + half, 1e-3f * half) << a;
  }
}

TEST(NerfSceneSpace, AnObjectOnItsOwnGetsTheCubeEveryCameraSeesWithRoomToSpare) {
  const glm::vec3 target(2, -1, 0.5f);
  const Dataset dataset = orbit_dataset(target, 8.0f, 0.7f, 40, true);
  const std::optional<CameraRig> rig = converging_rig(cameras_of(dataset.train));
  ASSERT_TRUE(rig);
  const SceneSpace space = scene_space_from_data(dataset, kFallback);
  EXPECT_FALSE(space.unbounded);
  expect_cube(space.box, rig->focus, 1.1f * rig->seen_radius);
  EXPECT_NEAR(glm::length(rig->focus - target), 0.0f, 1e-3f);
  // The cube scales with the rig: twice as far away, twice the size.
  const SceneSpace farther = scene_space_from_data(orbit_dataset(target, 16.0f, 0.7f, 40, true), kFallback);
  EXPECT_NEAR(farther.box.hi.x - farther.box.lo.x, 2.0f * (space.box.hi.x - space.box.lo.x), 1e-2f);
}

TEST(NerfSceneSpace, ImagesWithABackgroundMakeTheSceneUnboundedRoundTheCameras) {
  const glm::vec3 target(0, 0, 3);
  const Dataset dataset = orbit_dataset(target, 6.0f, 0.7f, 40, false);
  const SceneSpace space = scene_space_from_data(dataset, kFallback);
  EXPECT_TRUE(space.unbounded);
  // Every camera inside the uncontracted box, the nearest face at most 10 % farther out than
  // the farthest camera reaches along some axis.
  float reach = 0;
  for (const DatasetView& view : dataset.train) {
    const glm::vec3 c = view.camera.center_in_world();
    EXPECT_TRUE(glm::all(glm::greaterThan(c, space.box.lo)) && glm::all(glm::lessThan(c, space.box.hi)));
    const glm::vec3 offset = glm::abs(c - target);
    reach = std::max({reach, offset.x, offset.y, offset.z});
  }
  expect_cube(space.box, target, 1.1f * reach);
}

TEST(NerfSceneSpace, APointCloudGivesItsBoxAndCamerasThatDoNotConvergeTheFallback) {
  Dataset dataset = orbit_dataset(glm::vec3(0), 4.0f, 0.7f, 40, false);
  dataset.points = PointCloud{{-1, 0, 0, 3, 2, 1, 0, -2, 5}, {0, 0, 0, 0, 0, 0, 0, 0, 0}};
  const SceneSpace points = scene_space_from_data(dataset, kFallback);
  EXPECT_FALSE(points.unbounded);
  EXPECT_NEAR(points.box.lo.x, -1.0f - 0.2f - 1e-3f, 1e-5f);
  EXPECT_NEAR(points.box.hi.z, 5.0f + 0.25f + 1e-3f, 1e-5f);
  EXPECT_NEAR(points.box.lo.y, -2.0f - 0.2f - 1e-3f, 1e-5f);

  Dataset one_camera;
  one_camera.train.push_back(dataset.train.front());
  const SceneSpace fallback = scene_space_from_data(one_camera, kFallback);
  EXPECT_FALSE(fallback.unbounded);
  EXPECT_EQ(fallback.box.lo, kFallback.lo);
  EXPECT_EQ(fallback.box.hi, kFallback.hi);
}

}  // namespace
}  // namespace splat
