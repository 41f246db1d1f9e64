// The viewer's camera: it looks where it says, orbits about its target, shows dataset views
// exactly, and frames a model's points.
#include <gtest/gtest.h>

#include <glm/gtc/constants.hpp>

#include "apps/splat-viewer/view_controller.hpp"

namespace splat::viewer {
namespace {

glm::vec3 project(const Camera& c, glm::vec3 p) {
  const glm::vec3 q = c.camera_from_world(p);
  return {c.fx * q.x / q.z + c.cx, c.fy * q.y / q.z + c.cy, q.z};
}

TEST(ViewController, TheTargetIsAtTheImageCentreInFrontOfTheCamera) {
  ViewController view(glm::vec3(1, 2, 3), 5.0f, glm::vec3(0, 0, 1));
  const Camera c = view.camera(800, 600);
  const glm::vec3 p = project(c, view.target());
  EXPECT_NEAR(p.x, 400, 1e-3);
  EXPECT_NEAR(p.y, 300, 1e-3);
  EXPECT_NEAR(p.z, 5.0f, 1e-4);
  // Up in the world is up on screen (smaller y); the rotation is orthonormal.
  EXPECT_LT(project(c, view.target() + glm::vec3(0, 0, 0.1f)).y, 300);
  const glm::mat3 rrt = c.camera_from_world_rotation * glm::transpose(c.camera_from_world_rotation);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(rrt[i][j], i == j ? 1.0f : 0.0f, 1e-5);
}

TEST(ViewController, OrbitKeepsTheDistanceAndTheTargetCentred) {
  ViewController view(glm::vec3(0), 4.0f, glm::vec3(0, 0, 1));
  const glm::vec3 before = view.eye();
  view.orbit(200, 50, 600);
  EXPECT_NEAR(glm::length(view.eye() - view.target()), 4.0f, 1e-4);
  EXPECT_GT(glm::length(view.eye() - before), 0.5f);
  const glm::vec3 p = project(view.camera(640, 480), view.target());
  EXPECT_NEAR(p.x, 320, 1e-3);
  EXPECT_NEAR(p.y, 240, 1e-3);
  // Pitch stops short of the pole: dragging far up never flips the view.
  view.orbit(0, 1e5f, 600);
  EXPECT_LT(glm::dot(glm::normalize(view.eye() - view.target()), glm::vec3(0, 0, 1)), 1.0f);
}

TEST(ViewController, PanZoomFlyAndReset) {
  ViewController view(glm::vec3(0), 4.0f, glm::vec3(0, 0, 1));
  const glm::vec3 eye = view.eye();
  view.pan(100, 0, 600);
  // Dragging right moves the scene right: the old target now projects right of centre.
  EXPECT_GT(project(view.camera(600, 600), glm::vec3(0)).x, 300);
  view.zoom(2);
  EXPECT_NEAR(view.distance(), 4.0f * 0.81f, 1e-4);
  const glm::vec3 target = view.target();
  view.fly(1, 0, 0);  // forward: towards the target
  EXPECT_NEAR(glm::length(view.target() - target), 1.0f, 1e-5);
  view.reset();
  EXPECT_NEAR(glm::length(view.eye() - eye), 0.0f, 1e-5);
}

TEST(ViewController, ShowsADatasetCameraExactlyAndOrbitsOnFromIt) {
  ViewController free_view(glm::vec3(0.2f, 0, 0), 3.0f, glm::vec3(0, 0, 1));
  free_view.orbit(123, 40, 600);
  Camera dataset = free_view.camera(400, 300);
  dataset.cx = 190;  // an off-centre principal point survives
  ViewController view(glm::vec3(0), 3.0f, glm::vec3(0, 0, 1));
  view.show_camera(dataset);
  const Camera shown = view.camera(800, 600);
  EXPECT_EQ(shown.camera_from_world_rotation, dataset.camera_from_world_rotation);
  EXPECT_FLOAT_EQ(shown.cx, 380);
  EXPECT_FLOAT_EQ(shown.fx, 2 * dataset.fx);
  // A small orbit from there moves the camera only a little.
  view.orbit(1, 0, 600);
  EXPECT_LT(glm::length(view.eye() - dataset.center_in_world()), 0.05f);
}

TEST(ViewController, FramingIgnoresOutliersAndFitsTheRest) {
  std::vector<float> points;
  for (int i = 0; i <= 100; ++i) points.insert(points.end(), {-1.0f + 0.02f * i, 0.0f, 0.0f});
  points.insert(points.end(), {1000.0f, 1000.0f, 1000.0f});  // a floater
  const Framing f = frame_points(points.data(), points.size() / 3, glm::radians(60.0f));
  EXPECT_NEAR(f.center.x, 0.0f, 0.1f);
  EXPECT_LT(f.distance, 10.0f);
  EXPECT_GT(f.distance, 1.5f);
}

}  // namespace
}  // namespace splat::viewer
