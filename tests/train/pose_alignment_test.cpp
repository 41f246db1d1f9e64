// Pose alignment with the model fixed: from a known error in a tiny scene's camera, the
// correction found by gradient descent on the rasterizer's pose gradient brings the camera
// back to where the photograph was taken.
#include "splat/train/pose_alignment.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "splat/core/frame_change.hpp"
#include "splat/raster/projection_math.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

// Angle in degrees of the rotation between two camera-from-world rotations, from both the
// sine (the skew part, accurate near 0) and the cosine (the trace) of R = A Bᵀ.
double angle_between_deg(const glm::mat3& a, const glm::mat3& b) {
  const glm::dmat3 r = glm::dmat3(a) * glm::transpose(glm::dmat3(b));
  const glm::dvec3 skew(r[1][2] - r[2][1], r[2][0] - r[0][2], r[0][1] - r[1][0]);
  const double sine = glm::length(skew) / 2, cosine = (r[0][0] + r[1][1] + r[2][2] - 1.0) / 2.0;
  return std::atan2(sine, cosine) * 180.0 / 3.14159265358979323846;
}

// The photograph `camera` takes of `model`: its render.
Image photograph(const GaussianModel& model, const Camera& camera) {
  Rasterizer rasterizer;
  RenderResult photo;
  rasterizer.render(model, camera, RenderSettings{}, photo);
  return photo.color;
}

TEST(PoseAlignment, RecoversAKnownPerturbation) {
  GaussianModel model = test::random_model(400, 1, 5, 1.0f, 0.03f, 0.15f);
  for (float& o : model.opacity_logits) o = 2.0f;
  const Camera truth = test::looking_at_origin(64, 48, 3.0f, 0.8f);
  const RenderSettings render;
  const Image photo = photograph(model, truth);

  // 2 degrees about a tilted axis and 1 % of the camera distance off.
  PoseCorrection error;
  const double half = 2.0 * 3.14159265358979323846 / 180.0 / 2.0;
  const glm::vec3 axis = glm::normalize(glm::vec3(0.3f, 1.0f, -0.4f));
  error.rotation = glm::vec4(float(std::cos(half)), axis * float(std::sin(half)));
  error.translation = glm::vec3(0.02f, -0.015f, 0.015f);
  const Camera wrong = error.applied_to(truth);
  const double angle_before = angle_between_deg(wrong.camera_from_world_rotation, truth.camera_from_world_rotation);
  const double offset_before = glm::length(wrong.center_in_world() - truth.center_in_world());
  ASSERT_NEAR(angle_before, 2.0, 1e-3);

  // About the camera centre and about the scene's centre, 3 units in front (the two
  // parametrisations of a correction).
  for (float pivot_depth : {0.0f, 3.0f}) {
    SCOPED_TRACE(pivot_depth);
    PoseAlignmentSettings settings;
    settings.steps = 200;
    PoseCorrection start;
    start.pivot_depth = pivot_depth;
    const PoseAlignmentResult result = align_pose(model, wrong, photo, render, settings, 3.0f, start);
    const Camera aligned = result.correction.applied_to(wrong);
    const double angle_after =
        angle_between_deg(aligned.camera_from_world_rotation, truth.camera_from_world_rotation);
    const double offset_after = glm::length(aligned.center_in_world() - truth.center_in_world());
    std::printf("pivot %.0f: rotation error %.3f -> %.3f deg, centre offset %.4f -> %.4f, loss %.5f -> %.5f\n",
                pivot_depth, angle_before, angle_after, offset_before, offset_after, result.first_loss, result.loss);
    EXPECT_LT(angle_after, 0.1 * angle_before);
    EXPECT_LT(offset_after, 0.1 * offset_before);
    EXPECT_LT(result.loss, 0.2 * result.first_loss);
  }
}

TEST(PoseAlignment, LeavesTheRightPoseAlone) {
  GaussianModel model = test::random_model(300, 1, 6, 1.0f, 0.03f, 0.15f);
  const Camera truth = test::looking_at_origin(48, 40, 3.0f, 0.8f);
  PoseAlignmentSettings settings;
  settings.steps = 50;
  const Camera aligned =
      align_pose(model, truth, photograph(model, truth), RenderSettings{}, settings, 3.0f).correction.applied_to(truth);
  EXPECT_LT(angle_between_deg(aligned.camera_from_world_rotation, truth.camera_from_world_rotation), 0.05);
  EXPECT_LT(glm::length(aligned.center_in_world() - truth.center_in_world()), 2e-3);
}

// The refiner's first-moment decay (pose_adam_beta1) reaches its Adam: on a gradient that
// flips sign every step, as noise around a right pose does, averaging (0.9) moves the
// correction a tenth as far as none (0), while a gradient that keeps its sign moves it at the
// rate's pace either way.
TEST(PoseRefiner, ALongerFirstMomentAverageDampsAFlippingGradient) {
  const Camera base = test::looking_at_origin(64, 48, 3.0f, 0.8f);
  const auto path_length = [&](double beta1, bool flipping) {
    PoseRefiner refiner(1, 1.0f, {}, beta1);
    double length = 0;
    for (int step = 0; step < 40; ++step) {
      CameraPoseGradient gradient;
      gradient.translation = glm::vec3(flipping && step % 2 ? -1.0f : 1.0f, 0.0f, 0.0f);
      const glm::vec3 before = refiner.correction(0).translation;
      refiner.step(0, base, gradient, PoseLearningRates{1e-3f, 1e-3f});
      length += glm::length(refiner.correction(0).translation - before);
    }
    return length;
  };
  EXPECT_LT(path_length(0.9, true), 0.25 * path_length(0.0, true));
  EXPECT_NEAR(path_length(0.9, false), path_length(0.0, false), 0.05 * path_length(0.0, false));
  EXPECT_NEAR(path_length(0.0, false), 40 * 1e-3, 1e-4);
}

// Twelve cameras round the origin, each at its own turn and height.
std::vector<Camera> ring_of_cameras() {
  std::vector<Camera> cameras;
  for (int i = 0; i < 12; ++i) {
    FrameChange orbit;
    orbit.rotation = glm::mat3_cast(glm::angleAxis(glm::radians(30.0 * i), glm::dvec3(0, 1, 0)) *
                                    glm::angleAxis(glm::radians(10.0 * (i % 3) - 10.0), glm::dvec3(1, 0, 0)));
    cameras.push_back(orbit.applied_to(test::looking_at_origin(64, 48, 3.0f, 0.8f)));
  }
  return cameras;
}

TEST(PoseRefiner, CorrectionBetweenTwoPosesIsTheCorrectionThatMadeThem) {
  const Camera base = test::looking_at_origin(64, 48, 3.0f, 0.8f);
  PoseCorrection made;
  made.rotation = glm::vec4(0.999f, 0.02f, -0.03f, 0.01f);
  made.translation = glm::vec3(0.05f, -0.02f, 0.03f);
  made.pivot_depth = 3.0f;
  const PoseCorrection found = correction_between(base, made.applied_to(base), 3.0f);
  const glm::vec4 unit = made.rotation / glm::length(made.rotation);
  for (int a = 0; a < 4; ++a) EXPECT_NEAR(found.rotation[a], unit[a], 1e-5);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(found.translation[a], made.translation[a], 1e-5);
}

// A turn, shift and scale shared by every view's correction is the frame's drift, and
// hold_frame takes it out; a correction of one view alone is that view's own, and stays.
TEST(PoseRefiner, HoldFrameTakesOutTheSharedSimilarityOnly) {
  const std::vector<Camera> recorded = ring_of_cameras();
  FrameChange drift;
  drift.scale = 1.01;
  drift.rotation = glm::mat3_cast(glm::angleAxis(glm::radians(1.0), glm::normalize(glm::dvec3(0.2, 1, -0.3))));
  drift.translation = {0.03, -0.02, 0.05};
  PoseRefiner refiner(recorded.size(), 3.0f, std::vector<float>(recorded.size(), 3.0f));
  for (std::size_t v = 0; v < recorded.size(); ++v)
    refiner.set_correction(v, correction_between(recorded[v], drift.applied_to(recorded[v]), 3.0f));
  refiner.hold_frame(recorded);
  for (std::size_t v = 0; v < recorded.size(); ++v) {
    const Camera held = refiner.camera(v, recorded[v]);
    EXPECT_LT(angle_between_deg(held.camera_from_world_rotation, recorded[v].camera_from_world_rotation), 1e-3);
    EXPECT_LT(glm::length(held.center_in_world() - recorded[v].center_in_world()), 1e-4);
  }

  PoseRefiner one_view(recorded.size(), 3.0f, std::vector<float>(recorded.size(), 3.0f));
  PoseCorrection own;
  own.rotation = glm::vec4(std::cos(glm::radians(0.5f)), std::sin(glm::radians(0.5f)), 0.0f, 0.0f);  // 1°
  own.pivot_depth = 3.0f;
  one_view.set_correction(0, own);
  one_view.hold_frame(recorded);
  const double own_angle =
      angle_between_deg(one_view.camera(0, recorded[0]).camera_from_world_rotation, recorded[0].camera_from_world_rotation);
  EXPECT_GT(own_angle, 0.85);  // the shared part is a twelfth of it at most
  EXPECT_LT(own_angle, 1.0 + 1e-3);
}

}  // namespace
}  // namespace splat
