// The stability conditions change only what they say they change, by exactly the stated
// amounts, and the verdict rules as documented; the pose error that measures what refinement
// recovered ignores the frame and sees each camera's own error.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

#include "splat/core/error.hpp"
#include "splat/eval/pose_error.hpp"
#include "splat/eval/stability_conditions.hpp"

namespace splat {
namespace {

// Cameras on a circle of radius 4 looking at the origin, each image filled with its index.
Dataset ring_dataset(int train_views) {
  Dataset dataset;
  for (int i = 0; i < train_views + 2; ++i) {
    const double a = 2 * M_PI * i / (train_views + 2);
    const glm::dvec3 eye(4 * std::cos(a), 0.5, 4 * std::sin(a));
    const glm::dmat4 view = glm::lookAt(eye, glm::dvec3(0), glm::dvec3(0, 1, 0));  // OpenGL axes
    DatasetView v;
    v.name = std::string("v").append(std::to_string(i));
    // OpenGL to OpenCV axes: flip y and z.
    const glm::dmat3 flip(1, 0, 0, 0, -1, 0, 0, 0, -1);
    v.camera.camera_from_world_rotation = glm::mat3(flip * glm::dmat3(view));
    v.camera.camera_from_world_translation = glm::vec3(flip * glm::dvec3(view[3]));
    v.camera.width = v.camera.height = 4;
    v.image = Image(4, 4, 3, float(i));
    (i < train_views ? dataset.train : dataset.test).push_back(v);
  }
  dataset.scene_extent = 4.4f;
  dataset.points = PointCloud{{0, 0, 0}, {1, 1, 1}};
  return dataset;
}

double rotation_angle_deg(const glm::mat3& a, const glm::mat3& b) {
  const glm::dmat3 relative = glm::transpose(glm::dmat3(a)) * glm::dmat3(b);
  const double c = (relative[0][0] + relative[1][1] + relative[2][2] - 1) / 2;
  return glm::degrees(std::acos(std::clamp(c, -1.0, 1.0)));
}

std::vector<Camera> training_cameras(const Dataset& dataset) {
  std::vector<Camera> cameras;
  for (const DatasetView& view : dataset.train) cameras.push_back(view.camera);
  return cameras;
}

// `camera` in a world moved by x' = s·G·x + g: R' = R·Gᵀ, c' = s·G·c + g.
Camera in_moved_world(const Camera& camera, double s, const glm::dmat3& G, const glm::dvec3& g) {
  Camera moved = camera;
  const glm::dmat3 rotation = glm::dmat3(camera.camera_from_world_rotation) * glm::transpose(G);
  const glm::dvec3 centre = s * (G * glm::dvec3(camera.center_in_world())) + g;
  moved.camera_from_world_rotation = glm::mat3(rotation);
  moved.camera_from_world_translation = glm::vec3(-(rotation * centre));
  return moved;
}

TEST(PoseError, IsZeroForTheTruePosesInAnotherFrame) {
  const std::vector<Camera> truth = training_cameras(ring_dataset(8));
  const glm::dmat3 G(glm::rotate(glm::dmat4(1.0), glm::radians(30.0), glm::normalize(glm::dvec3(1, 2, 0.5))));
  std::vector<Camera> moved;
  for (const Camera& c : truth) moved.push_back(in_moved_world(c, 1.7, G, {0.3, -2.0, 5.0}));
  const PoseError e = pose_error(moved, truth);
  EXPECT_LT(e.max_rotation_deg, 2e-3);
  EXPECT_LT(e.max_translation, 1e-4);
  EXPECT_NEAR(e.scale, 1 / 1.7, 1e-5);
}

TEST(PoseError, SeesOneCameraTurnedAboutItsCentre) {
  const std::vector<Camera> truth = training_cameras(ring_dataset(6));
  std::vector<Camera> estimated = truth;
  const glm::dmat3 turn(glm::rotate(glm::dmat4(1.0), glm::radians(2.0), glm::dvec3(0, 0, 1)));
  estimated[2].camera_from_world_rotation = glm::mat3(glm::dmat3(truth[2].camera_from_world_rotation) * turn);
  estimated[2].camera_from_world_translation =
      glm::vec3(-(glm::dmat3(estimated[2].camera_from_world_rotation) * glm::dvec3(truth[2].center_in_world())));
  const PoseError e = pose_error(estimated, truth);
  EXPECT_NEAR(e.max_rotation_deg, 2.0, 2e-3);
  EXPECT_NEAR(e.mean_rotation_deg, 2.0 / 6.0, 1e-3);
  EXPECT_LT(e.max_translation, 1e-4);
}

TEST(PoseError, MeasuresPoseNoiseAtMostItsSize) {
  const Dataset dataset = ring_dataset(12);
  const PoseError e = pose_error(training_cameras(with_pose_noise(dataset, 1.0, 0.01, 3)), training_cameras(dataset));
  // The similarity fit absorbs only what the cameras share: most of the noise stays (the fit's
  // own turn, a fraction of a degree for 12 centres moved by 1 %, adds to some cameras).
  EXPECT_LE(e.max_rotation_deg, 1.5);
  EXPECT_GT(e.mean_rotation_deg, 0.5);
  EXPECT_LE(e.mean_translation, 0.01 * 4.4 * 1.2);
  EXPECT_GT(e.mean_translation, 0.01 * 4.4 * 0.3);
  EXPECT_THROW(pose_error(training_cameras(dataset), {}), ArgumentError);
}

TEST(StabilityConditions, FewerViewsAreSpreadEvenlyAndTheExtentFollowsThem) {
  const Dataset dataset = ring_dataset(12);
  const Dataset four = with_training_views(dataset, 4);
  ASSERT_EQ(four.train.size(), 4u);
  EXPECT_EQ(four.train[0].name, "v0");
  EXPECT_EQ(four.train[1].name, "v3");
  EXPECT_EQ(four.train[3].name, "v9");
  EXPECT_EQ(four.test.size(), dataset.test.size());
  EXPECT_TRUE(four.points.has_value());
  // Four cameras on a circle of radius 4 (at 0°, 77°, 154°, 231°): the extent is recomputed.
  EXPECT_NE(four.scene_extent, dataset.scene_extent);
  EXPECT_GT(four.scene_extent, 1.0f);
  EXPECT_EQ(with_training_views(dataset, 50).train.size(), 12u);
  EXPECT_THROW(with_training_views(dataset, 0), ArgumentError);
}

TEST(StabilityConditions, PoseNoiseTurnsAndMovesEachTrainingCameraByExactlyTheAmount) {
  const Dataset dataset = ring_dataset(6);
  const Dataset noisy = with_pose_noise(dataset, 2.0, 0.05, 7);
  ASSERT_EQ(noisy.train.size(), dataset.train.size());
  for (std::size_t i = 0; i < dataset.train.size(); ++i) {
    const Camera &before = dataset.train[i].camera, &after = noisy.train[i].camera;
    EXPECT_NEAR(rotation_angle_deg(before.camera_from_world_rotation, after.camera_from_world_rotation), 2.0, 2e-3);
    EXPECT_NEAR(glm::length(after.center_in_world() - before.center_in_world()), 0.05 * 4.4, 1e-4);
  }
  for (std::size_t i = 0; i < dataset.test.size(); ++i) {
    EXPECT_EQ(noisy.test[i].camera.camera_from_world_rotation, dataset.test[i].camera.camera_from_world_rotation);
    EXPECT_EQ(noisy.test[i].camera.camera_from_world_translation, dataset.test[i].camera.camera_from_world_translation);
  }
  // Seeded: the same seed, the same poses; another seed, others.
  const Dataset again = with_pose_noise(dataset, 2.0, 0.05, 7), other = with_pose_noise(dataset, 2.0, 0.05, 8);
  EXPECT_EQ(again.train[3].camera.camera_from_world_translation, noisy.train[3].camera.camera_from_world_translation);
  EXPECT_NE(other.train[3].camera.camera_from_world_translation, noisy.train[3].camera.camera_from_world_translation);
}

TEST(StabilityConditions, RandomInitialisationDropsOnlyThePointCloud) {
  const Dataset dataset = ring_dataset(3);
  const Dataset random = without_point_cloud(dataset);
  EXPECT_FALSE(random.points.has_value());
  EXPECT_EQ(random.train.size(), dataset.train.size());
}

TEST(StabilityConditions, BackgroundOnlyPsnrIsTheEmptyModelsScore) {
  std::vector<DatasetView> test(2);
  test[0].image = Image(2, 2, 3, 0.9f);  // MSE 0.01 against white → 20 dB
  test[1].image = Image(2, 2, 3, 0.99f);  // MSE 1e-4 → 40 dB
  const float white[3] = {1, 1, 1};
  EXPECT_NEAR(background_only_psnr(test, white), 30.0, 1e-4);
}

TEST(StabilityConditions, VerdictRules) {
  // Background alone scores 15 dB, so the absolute floor is max(15 + 3, 20) = 20 dB; the
  // method's baseline 30 dB.
  EXPECT_STREQ(verdict_name(classify_run(true, 29, 15, 30)), "diverged");
  EXPECT_STREQ(verdict_name(classify_run(false, 15.9, 15, 30)), "collapsed");
  EXPECT_STREQ(verdict_name(classify_run(false, 16.1, 15, 30)), "failed");
  EXPECT_STREQ(verdict_name(classify_run(false, 19.9, 15, 30)), "failed");
  EXPECT_STREQ(verdict_name(classify_run(false, 20.1, 15, 30)), "degraded");
  EXPECT_STREQ(verdict_name(classify_run(false, 26.9, 15, 30)), "degraded");
  EXPECT_STREQ(verdict_name(classify_run(false, 27.1, 15, 30)), "ok");
  EXPECT_STREQ(verdict_name(classify_run(false, 20.1, 15, std::nullopt)), "ok");
  EXPECT_STREQ(verdict_name(classify_run(false, std::nan(""), 15, 30)), "collapsed");
}

// A method that fails outright fails in every condition, its baseline included: the verdict
// is not only relative to its own baseline.
TEST(StabilityConditions, AFailedBaselineDoesNotMakeItsConditionsOk) {
  EXPECT_STREQ(verdict_name(classify_run(false, 17.9, 5.4, std::nullopt)), "failed");  // the baseline
  EXPECT_STREQ(verdict_name(classify_run(false, 17.5, 5.4, 17.9)), "failed");
}

TEST(StabilityConditions, TheFloorIsTheHigherOfTheMarginAndTheAbsoluteFloor) {
  const VerdictRules rules;
  EXPECT_DOUBLE_EQ(rules.failure_psnr(5.4), 20.0);   // a background far from the scene's
  EXPECT_DOUBLE_EQ(rules.failure_psnr(25.0), 28.0);  // a background that is most of the image
  EXPECT_STREQ(verdict_name(classify_run(false, 27.5, 25.0, std::nullopt)), "failed");
  EXPECT_STREQ(verdict_name(classify_run(false, 28.5, 25.0, std::nullopt)), "ok");
}

}  // namespace
}  // namespace splat
