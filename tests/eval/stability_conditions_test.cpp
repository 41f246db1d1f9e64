// The stability conditions change only what they say they change, by exactly the stated
// amounts, and the verdict rules as documented.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

#include "splat/core/error.hpp"
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
  // Background alone scores 15 dB; the method's baseline 30 dB.
  EXPECT_STREQ(verdict_name(classify_run(true, 29, 15, 30)), "diverged");
  EXPECT_STREQ(verdict_name(classify_run(false, 15.9, 15, 30)), "collapsed");
  EXPECT_STREQ(verdict_name(classify_run(false, 16.1, 15, 30)), "degraded");
  EXPECT_STREQ(verdict_name(classify_run(false, 26.9, 15, 30)), "degraded");
  EXPECT_STREQ(verdict_name(classify_run(false, 27.1, 15, 30)), "ok");
  EXPECT_STREQ(verdict_name(classify_run(false, 20, 15, std::nullopt)), "ok");
  EXPECT_STREQ(verdict_name(classify_run(false, std::nan(""), 15, 30)), "collapsed");
}

}  // namespace
}  // namespace splat
