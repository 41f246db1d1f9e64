// The NeRF trainer's start and schedule: an untrained field that is nearly transparent (no
// fog to clear, the cause of the collapse on thin structures), and a learning rate that
// decays over a time budget when there is one.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "splat/core/error.hpp"
#include "splat/data/orbit_cameras.hpp"
#include "splat/train/nerf_trainer.hpp"

namespace splat {
namespace {

// Four white 24 × 24 views around the origin (the content does not matter here).
Dataset small_dataset() {
  Dataset dataset;
  OrbitRig rig;
  rig.count = 4;
  rig.width = rig.height = 24;
  for (const Camera& camera : orbit_cameras(rig)) dataset.train.push_back({"v", camera, Image(24, 24, 3, 1.0f)});
  dataset.scene_extent = 4.4f;
  return dataset;
}

NerfTrainingConfig small_config(float density_bias) {
  NerfTrainingConfig config;
  config.model.fine = config.model.coarse;
  config.density_bias_init = density_bias;
  config.background[0] = config.background[1] = config.background[2] = 0.0f;  // black: fog shows
  return config;
}

// Mean brightness of a view rendered by an untrained field over a black background: the
// field's own opacity and colour.
double untrained_brightness(float density_bias) {
  const Dataset dataset = small_dataset();
  NerfTrainer trainer(dataset, small_config(density_bias));
  const Image image = trainer.render(dataset.train[0].camera);
  double sum = 0;
  for (const float v : image.data) sum += v;
  return sum / double(image.data.size());
}

TEST(NerfTrainer, UntrainedFieldIsNearlyTransparent) {
  // Glorot weights with a zero density bias: a grey fog over much of the view.
  EXPECT_GT(untrained_brightness(0.0f), 0.2);
  // The default starts at σ ≈ 0.05 per unit: a ray through the ±1.5 box keeps ≥ 80 % of the
  // background.
  EXPECT_EQ(NerfTrainingConfig{}.density_bias_init, -3.0f);
  EXPECT_LT(untrained_brightness(-3.0f), 0.1);
}

TEST(NerfTrainer, LearningRateDecaysOverTheTimeBudget) {
  const Dataset dataset = small_dataset();
  NerfTrainingConfig config = small_config(-3.0f);
  config.max_seconds = 60;
  config.rays_per_batch = 64;
  config.lr_decay_iterations = 2;
  NerfTrainer trainer(dataset, config);
  EXPECT_FLOAT_EQ(trainer.learning_rate(), float(config.lr_init));
  trainer.set_time_budget_fraction(0.5);  // halfway: the geometric mean of the two rates
  const double halfway = std::sqrt(config.lr_init * config.lr_final);
  EXPECT_NEAR(trainer.learning_rate(), halfway, 1e-9);
  // Past lr_decay_iterations the budget still sets the pace: a run that makes more
  // iterations than that horizon in its time keeps decaying to its end.
  for (int i = 0; i < 3; ++i) trainer.step();
  EXPECT_NEAR(trainer.learning_rate(), halfway, 1e-9);
  trainer.set_time_budget_fraction(1.0);
  EXPECT_NEAR(trainer.learning_rate(), config.lr_final, 1e-9);

  // Without a budget, or with the schedule on iterations, the iterations set it.
  for (const bool budget : {false, true}) {
    NerfTrainingConfig by_iterations_config = config;
    by_iterations_config.max_seconds = budget ? 60 : 0;
    by_iterations_config.schedule_follows_budget = !budget;
    NerfTrainer by_iterations(dataset, by_iterations_config);
    by_iterations.set_time_budget_fraction(0.5);
    EXPECT_FLOAT_EQ(by_iterations.learning_rate(), float(config.lr_init));
    for (int i = 0; i < 3; ++i) by_iterations.step();
    EXPECT_NEAR(by_iterations.learning_rate(), config.lr_final, 1e-9);
  }
}

// The model a run scores and saves is the average of Adam's iterates: from halfway through
// the rate's decay each step moves it (1 − decay) of the way to the iterate; before, it is
// the iterate.
TEST(NerfTrainer, TheModelIsTheRunningAverageOfTheIterates) {
  const Dataset dataset = small_dataset();
  NerfTrainingConfig config = small_config(-3.0f);
  config.rays_per_batch = 64;
  config.lr_decay_iterations = 4;  // halfway after step 2
  config.parameter_average_decay = 0.3f;
  config.occupancy_warmup = config.occupancy_interval = 4;  // a grid update within the steps
  NerfTrainer trainer(dataset, config);
  const auto parameters = [](const NerfModel& m) {
    std::vector<float> p(m.coarse.parameters().begin(), m.coarse.parameters().end());
    p.insert(p.end(), m.fine.parameters().begin(), m.fine.parameters().end());
    return p;
  };
  std::vector<float> expected = parameters(trainer.iterate());
  ASSERT_EQ(parameters(trainer.model()), expected);
  for (int t = 0; t < 6; ++t) {
    const bool averaging = trainer.schedule_progress() >= kAverageFromProgress;
    EXPECT_EQ(averaging, t >= 2);
    trainer.step();
    const float d = averaging ? 0.3f : 0.0f;
    const std::vector<float> iterate = parameters(trainer.iterate());
    for (std::size_t i = 0; i < expected.size(); ++i) expected[i] = d * expected[i] + (1 - d) * iterate[i];
    ASSERT_EQ(parameters(trainer.model()), expected) << "after step " << t + 1;
    if (averaging) ASSERT_NE(parameters(trainer.model()), iterate) << "after step " << t + 1;
    else ASSERT_EQ(parameters(trainer.model()), iterate) << "after step " << t + 1;
  }
  // The average renders through the iterate's grid, updated at step 4.
  EXPECT_GT(*std::max_element(trainer.iterate().grid.values().begin(), trainer.iterate().grid.values().end()), 0.0f);
  EXPECT_TRUE(std::equal(trainer.model().grid.values().begin(), trainer.model().grid.values().end(),
                         trainer.iterate().grid.values().begin()));

  // Off: the model is the iterate.
  config.parameter_average_decay = 0;
  NerfTrainer plain(dataset, config);
  for (int t = 0; t < 3; ++t) plain.step();
  EXPECT_EQ(&plain.model(), &plain.iterate());
  EXPECT_THROW(from_json(nlohmann::json{{"parameter_average_decay", 1.0}}, config), ArgumentError);
}

TEST(NerfTrainer, RejectsANonFiniteDensityBias) {
  NerfTrainingConfig config;
  EXPECT_THROW(from_json(nlohmann::json{{"density_bias_init", nullptr}}, config), ArgumentError);
}

TEST(NerfTrainer, AConfiguredBoxIsKeptAndOtherwiseTheDataPlacesIt) {
  NerfTrainingConfig config;
  EXPECT_TRUE(config.box_from_data);
  from_json(nlohmann::json{{"model", {{"coarse_samples", 32}}}}, config);
  EXPECT_TRUE(config.box_from_data);
  from_json(nlohmann::json{{"model", {{"box_min", {-3, -3, -3}}, {"box_max", {3, 3, 3}}}}}, config);
  EXPECT_FALSE(config.box_from_data);
  EXPECT_EQ(config.model.box.hi, glm::vec3(3.0f));
  NerfTrainingConfig unbounded;
  from_json(nlohmann::json{{"model", {{"unbounded", true}}}}, unbounded);
  EXPECT_FALSE(unbounded.box_from_data);
  EXPECT_TRUE(unbounded.model.unbounded);
  // A written config.json reads back the same, either way.
  for (bool from_data : {false, true}) {
    config.box_from_data = from_data;
    NerfTrainingConfig round_trip;
    from_json(to_json(config), round_trip);
    EXPECT_EQ(round_trip.box_from_data, from_data);
  }
}

// A small NGP: the preset's shape with tables of 2¹⁰ entries, few samples and rays.
NerfTrainingConfig small_ngp_config() {
  NerfTrainingConfig config = nerf_training_preset("ngp");
  for (NerfMlpConfig* mlp : {&config.model.coarse, &config.model.fine}) {
    mlp->hash.levels = 4;
    mlp->hash.table_log2 = 10;
    mlp->hash.max_resolution = 64;
  }
  config.model.coarse_samples = 16;
  config.model.fine_samples = 8;
  config.rays_per_batch = 64;
  return config;
}

// Views with an alpha channel, all of it `alpha`: the image is white composited over white.
Dataset transparent_dataset(float alpha) {
  Dataset dataset = small_dataset();
  for (DatasetView& view : dataset.train) view.alpha = Image(24, 24, 1, alpha);
  return dataset;
}

TEST(NerfTrainer, RandomBackgroundsShowBehindTransparentPixelsOnly) {
  // An empty field renders each ray's own background; through fully transparent pixels the
  // target is the photo on that same colour, so the loss is zero: the render and the target
  // take one colour per ray.
  NerfTrainingConfig config = small_ngp_config();
  ASSERT_TRUE(config.random_background);
  config.density_bias_init = -30.0f;
  const Dataset transparent = transparent_dataset(0.0f);
  NerfTrainer empty(transparent, config);
  EXPECT_LT(empty.step().loss, 1e-10);
  // Photos without transparency train as they did without random backgrounds, bit for bit.
  config.density_bias_init = -3.0f;
  const Dataset opaque = small_dataset();
  NerfTrainer with(opaque, config);
  config.random_background = false;
  NerfTrainer without(opaque, config);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(with.step().loss, without.step().loss);
  EXPECT_TRUE(std::equal(with.model().fine.parameters().begin(), with.model().fine.parameters().end(),
                         without.model().fine.parameters().begin()));
  // Where the photos are transparent, the targets differ from the fixed background's.
  config = small_ngp_config();
  NerfTrainer random_target(transparent, config);
  config.random_background = false;
  NerfTrainer fixed_target(transparent, config);
  EXPECT_NE(random_target.step().loss, fixed_target.step().loss);
}

}  // namespace
}  // namespace splat
