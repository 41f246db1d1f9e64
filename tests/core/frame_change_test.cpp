// The change of frame between recorded and refined poses: a known similarity is recovered
// from cameras it moved (on a sphere, on a line, a single one), a moved camera sees the moved
// scene as the old one saw the old scene, and per-view errors average out of the fit.
#include "splat/core/frame_change.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "splat/core/error.hpp"

namespace splat {
namespace {

glm::dmat3 turn(double degrees, glm::dvec3 axis) {
  return glm::mat3_cast(glm::angleAxis(glm::radians(degrees), glm::normalize(axis)));
}

Camera camera_at(const glm::dmat3& rotation, const glm::dvec3& centre) {
  Camera c;
  c.camera_from_world_rotation = glm::mat3(rotation);
  c.camera_from_world_translation = glm::vec3(-(rotation * centre));
  c.fx = c.fy = 500;
  c.cx = c.cy = 200;
  c.width = c.height = 400;
  return c;
}

FrameChange known_change() {
  FrameChange change;
  change.scale = 1.3;
  change.rotation = turn(20, {1, 2, -0.5});
  change.translation = {0.5, -1.0, 2.0};
  return change;
}

std::vector<Camera> random_cameras(int count, unsigned seed, bool line_only = false) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Camera> cameras;
  for (int i = 0; i < count; ++i) {
    const glm::dvec3 centre = line_only ? glm::dvec3(0.3 * i, 0.1, 4.0) : glm::dvec3(4 * u(rng), 4 * u(rng), 4 * u(rng));
    cameras.push_back(camera_at(turn(60 * u(rng), {u(rng), u(rng), 1.0}), centre));
  }
  return cameras;
}

std::vector<Camera> moved(const std::vector<Camera>& cameras, const FrameChange& change) {
  std::vector<Camera> out;
  for (const Camera& c : cameras) out.push_back(change.applied_to(c));
  return out;
}

void expect_same_change(const FrameChange& found, const FrameChange& truth, double tolerance) {
  EXPECT_NEAR(found.scale, truth.scale, tolerance);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(found.translation[c], truth.translation[c], tolerance * 10);
    for (int r = 0; r < 3; ++r) EXPECT_NEAR(found.rotation[c][r], truth.rotation[c][r], tolerance);
  }
}

TEST(FrameChange, MovedCameraSeesMovedSceneAlike) {
  const FrameChange change = known_change();
  const Camera old_camera = camera_at(turn(30, {0, 1, 0}), {1, 2, -4});
  const Camera new_camera = change.applied_to(old_camera);
  for (const glm::dvec3 x : {glm::dvec3(0, 0, 0), glm::dvec3(0.7, -0.3, 1.1), glm::dvec3(-1, 1, 0.5)}) {
    const glm::dvec3 x_new = change.scale * (change.rotation * x) + change.translation;
    const glm::dvec3 a = glm::dvec3(old_camera.camera_from_world(glm::vec3(x)));
    const glm::dvec3 b = glm::dvec3(new_camera.camera_from_world(glm::vec3(x_new)));
    EXPECT_NEAR(b.z, change.scale * a.z, 1e-4);               // depth scales with the scene
    EXPECT_NEAR(b.x / b.z, a.x / a.z, 1e-6);                  // the same pixel
    EXPECT_NEAR(b.y / b.z, a.y / a.z, 1e-6);
  }
}

TEST(FrameChange, RecoversAKnownSimilarity) {
  const std::vector<Camera> recorded = random_cameras(12, 1);
  expect_same_change(fit_frame_change(recorded, moved(recorded, known_change())), known_change(), 2e-6);
}

TEST(FrameChange, RecoversItFromCamerasInARow) {
  // Centres on one line leave a fit of the centres free to turn about it; orientations do not.
  const std::vector<Camera> recorded = random_cameras(6, 2, true);
  expect_same_change(fit_frame_change(recorded, moved(recorded, known_change())), known_change(), 2e-6);
}

TEST(FrameChange, OneCameraMapsOntoItsRefinedPose) {
  const std::vector<Camera> recorded = random_cameras(1, 3);
  const std::vector<Camera> refined = moved(recorded, known_change());
  const FrameChange found = fit_frame_change(recorded, refined);
  EXPECT_EQ(found.scale, 1.0);  // one centre carries no scale
  const Camera mapped = found.applied_to(recorded[0]);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(mapped.camera_from_world_translation[c], refined[0].camera_from_world_translation[c], 1e-5);
    for (int r = 0; r < 3; ++r)
      EXPECT_NEAR(mapped.camera_from_world_rotation[c][r], refined[0].camera_from_world_rotation[c][r], 1e-6);
  }
}

TEST(FrameChange, PerViewErrorsAverageOut) {
  // Each refined view off by its own 0.5° turn about its centre: the common change is found
  // far closer than any one view's error.
  const std::vector<Camera> recorded = random_cameras(200, 4);
  std::vector<Camera> refined = moved(recorded, known_change());
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0, 1);
  for (Camera& c : refined) {
    const glm::dvec3 centre = glm::dvec3(c.center_in_world());
    c = camera_at(turn(0.5, {n(rng), n(rng), n(rng)}) * glm::dmat3(c.camera_from_world_rotation), centre);
  }
  const FrameChange found = fit_frame_change(recorded, refined);
  const glm::dmat3 residual = found.rotation * glm::transpose(known_change().rotation);
  const double sine = glm::length(glm::dvec3(residual[1][2] - residual[2][1], residual[2][0] - residual[0][2],
                                             residual[0][1] - residual[1][0])) / 2;
  EXPECT_LT(glm::degrees(std::asin(sine)), 0.15);
  EXPECT_NEAR(found.scale, 1.3, 1e-4);
}

TEST(FrameChange, InverseUndoesIt) {
  const std::vector<Camera> cameras = random_cameras(6, 9);
  const std::vector<Camera> back = moved(moved(cameras, known_change()), known_change().inverse());
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    EXPECT_LT(glm::length(back[i].center_in_world() - cameras[i].center_in_world()), 1e-4f);
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r)
        EXPECT_NEAR(back[i].camera_from_world_rotation[c][r], cameras[i].camera_from_world_rotation[c][r], 1e-5);
  }
}

TEST(FrameChange, PointSimilarityRecoversAKnownOne) {
  const FrameChange truth = known_change();
  std::vector<glm::dvec3> from, to;
  for (const Camera& c : random_cameras(5, 7)) {
    from.push_back(glm::dvec3(c.center_in_world()));
    to.push_back(truth.scale * (truth.rotation * from.back()) + truth.translation);
  }
  expect_same_change(fit_point_similarity(from, to), truth, 1e-9);
  EXPECT_THROW(fit_point_similarity({from[0], from[0], from[0]}, {to[0], to[1], to[2]}), ArgumentError);
  EXPECT_THROW(fit_point_similarity({from[0], from[1]}, {to[0], to[1]}), ArgumentError);
}

TEST(FrameChange, RejectsMismatchedSets) {
  EXPECT_THROW(fit_frame_change(random_cameras(3, 6), random_cameras(2, 6)), ArgumentError);
  EXPECT_THROW(fit_frame_change({}, {}), ArgumentError);
}

}  // namespace
}  // namespace splat
