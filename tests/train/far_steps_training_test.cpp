// The trainer grows far content's position steps only where the cameras placed a random
// start through their frusta (an opaque scene that may reach any distance).
#include <gtest/gtest.h>

#include <cmath>

#include "splat/data/orbit_cameras.hpp"
#include "splat/train/splat_trainer.hpp"

namespace splat {
namespace {

// Eight views round the origin of a flat sky-blue image; the frame shows the background
// (white) or not.
Dataset blue_orbit(bool background_left_out) {
  OrbitRig rig;
  rig.count = 8;
  rig.width = rig.height = 24;
  Dataset dataset;
  for (const Camera& camera : orbit_cameras(rig)) {
    DatasetView view;
    view.camera = camera;
    view.image = Image(24, 24, 3, 0.7f);
    view.frame_background_share = background_left_out ? 1.0f : 0.0f;
    dataset.train.push_back(view);
  }
  dataset.test = {dataset.train[0]};
  dataset.scene_extent = 1.1f * rig.radius;
  return dataset;
}

GaussianModel after_steps(const Dataset& dataset, float exponent, int steps) {
  SplatTrainingConfig config = splat_training_preset("compact");
  config.random_init_points = 400;
  config.far_position_step_exponent = exponent;
  SplatTrainer trainer(dataset, config);
  for (int i = 0; i < steps; ++i) trainer.step();
  return trainer.model();
}

TEST(FarStepsTraining, OnlyFarGaussiansOfAFrustaStartMoveFurther) {
  const Dataset opaque = blue_orbit(false);
  // One step: both start from the same model, so every gradient is the same.
  const GaussianModel plain = after_steps(opaque, 0.0f, 1), far = after_steps(opaque, 4.0f, 1);
  SplatTrainingConfig config = splat_training_preset("compact");
  config.random_init_points = 400;
  InitialisationReport report;
  const GaussianModel start = initial_model(opaque, config, &report);
  ASSERT_EQ(report.kind, "frusta");
  ASSERT_EQ(plain.size(), start.size());
  ASSERT_EQ(far.size(), start.size());
  std::size_t near_same = 0, near_count = 0, far_moved_more = 0, far_count = 0;
  for (std::size_t i = 0; i < start.size(); ++i) {
    const glm::vec3 p(start.means[3 * i], start.means[3 * i + 1], start.means[3 * i + 2]);
    double plain_step = 0, far_step = 0;
    bool same = true;
    for (int a = 0; a < 3; ++a) {
      plain_step += std::abs(plain.means[3 * i + a] - start.means[3 * i + a]);
      far_step += std::abs(far.means[3 * i + a] - start.means[3 * i + a]);
      same = same && plain.means[3 * i + a] == far.means[3 * i + a];
    }
    // Well inside or well beyond the cameras' distance (a Gaussian near it may cross).
    const float r = glm::length(p - report.centre);
    if (r < 0.8f * report.distance) ++near_count, near_same += same;
    if (r > 2.0f * report.distance && plain_step > 0) ++far_count, far_moved_more += far_step > 10 * plain_step;
  }
  ASSERT_GT(near_count, 0u);
  ASSERT_GT(far_count, 50u);
  EXPECT_EQ(near_same, near_count);
  EXPECT_EQ(far_moved_more, far_count);
}

TEST(FarStepsTraining, AnObjectInACubeIsUntouched) {
  const Dataset object = blue_orbit(true);
  EXPECT_EQ(after_steps(object, 0.0f, 3).means, after_steps(object, 4.0f, 3).means);
}

}  // namespace
}  // namespace splat
