// Where a rig of cameras looks: focus, distance and the ball every camera sees.
#include "splat/core/camera_rig.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "splat/data/orbit_cameras.hpp"

namespace splat {
namespace {

// Cameras at several elevations on circles round `target`, as the scenes' orbit rigs and
// the Blender sets place them.
std::vector<Camera> orbit(const glm::vec3& target, float radius, float fov_x) {
  std::vector<Camera> all;
  for (float elevation : {0.2f, 0.5f, 0.9f}) {
    OrbitRig rig;
    rig.count = 7;
    rig.radius = radius;
    rig.elevation_radians = elevation;
    rig.fov_x_radians = fov_x;
    rig.width = 160;
    rig.height = 120;
    rig.target = target;
    for (const Camera& c : orbit_cameras(rig)) all.push_back(c);
  }
  return all;
}

TEST(CameraRig, AnOrbitFocusesOnItsTarget) {
  const glm::vec3 target(0.3f, -0.4f, 1.2f);
  const std::vector<Camera> cameras = orbit(target, 4.0f, 0.9f);
  const auto rig = converging_rig(cameras);
  ASSERT_TRUE(rig);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(rig->focus[a], target[a], 1e-4);
  EXPECT_NEAR(rig->distance, 4.0f, 1e-4);
  // Every camera looks straight at the target: the ball fills the narrower (vertical) half
  // field of view.
  const float half_fov_y = std::atan(cameras[0].tan_half_fov_y());
  EXPECT_NEAR(rig->seen_radius, 4.0f * std::sin(half_fov_y), 1e-4);
}

TEST(CameraRig, TheSeenBallIsInsideEveryView) {
  std::vector<Camera> cameras = orbit(glm::vec3(0.0f), 3.0f, 0.8f);
  // One camera turned a little off the target: the shared ball shrinks to what it still sees.
  cameras[4] = look_at(cameras[4].center_in_world(), glm::vec3(0.3f, 0.0f, 0.0f), {0, 0, 1}, cameras[4].fx,
                       cameras[4].fy, cameras[4].width, cameras[4].height);
  const auto rig = converging_rig(cameras);
  ASSERT_TRUE(rig);
  EXPECT_GT(rig->seen_radius, 0.1f);
  EXPECT_LT(rig->seen_radius, 3.0f * std::sin(std::atan(cameras[0].tan_half_fov_y())) - 0.01f);
  // Points on the ball's surface in many directions project inside every image.
  for (int i = 0; i < 50; ++i) {
    const float t = 0.7f * float(i), s = 1.3f * float(i);
    const glm::vec3 dir = glm::normalize(glm::vec3(std::cos(t) * std::sin(s), std::sin(t) * std::sin(s), std::cos(s)));
    for (const Camera& camera : cameras) EXPECT_TRUE(in_view(camera, rig->focus + 0.999f * rig->seen_radius * dir));
  }
}

TEST(CameraRig, ParallelOrOutwardAxesHaveNoFocus) {
  // Forward-facing: cameras side by side, all looking the same way.
  std::vector<Camera> parallel;
  for (int i = 0; i < 5; ++i)
    parallel.push_back(look_at({float(i), 0, 0}, {float(i), 10, 0}, {0, 0, 1}, 100, 100, 100, 100));
  EXPECT_FALSE(converging_rig(parallel));
  // A panorama turned outwards from a circle: the axes meet behind the cameras.
  std::vector<Camera> outward;
  for (int i = 0; i < 8; ++i) {
    const glm::vec3 at(std::cos(0.8f * i), std::sin(0.8f * i), 0.0f);
    outward.push_back(look_at(at, 3.0f * at, {0, 0, 1}, 100, 100, 100, 100));
  }
  EXPECT_FALSE(converging_rig(outward));
  EXPECT_FALSE(converging_rig(std::vector<Camera>(1, parallel[0])));
}

TEST(CameraRig, InViewIsTheImageInFrontOfTheCamera) {
  const Camera camera = look_at({0, -5, 0}, {0, 0, 0}, {0, 0, 1}, 100, 100, 100, 100);
  EXPECT_TRUE(in_view(camera, {0, 0, 0}));
  EXPECT_TRUE(in_view(camera, {0.9f, 0, 0}));     // 0.9 / 5 · 100 = 18 px right of the centre
  EXPECT_FALSE(in_view(camera, {3.0f, 0, 0}));    // 60 px right: outside the 100 px image
  EXPECT_FALSE(in_view(camera, {0, -10, 0}));     // behind
  const glm::vec3 axis = optical_axis(camera);
  EXPECT_NEAR(axis.y, 1.0f, 1e-6);
}

}  // namespace
}  // namespace splat
