// The validation holdout: which views it takes, when it keeps a model, how it decides, and a
// trainer that holds views out, restores its best model when they say it has fallen, and
// resumes from a checkpoint to the same end.
#include "splat/train/validation_holdout.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "splat/data/orbit_cameras.hpp"
#include "splat/train/splat_trainer.hpp"
#include "splat/train/validation_views.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

// A capture on an orbit: cameras evenly spaced, so no view is more redundant than another.
Dataset capture(int train_views, bool with_points) {
  OrbitRig rig;
  rig.count = train_views;
  rig.width = rig.height = 8;
  Dataset dataset;
  const std::vector<Camera> cameras = orbit_cameras(rig);
  for (int i = 0; i < train_views; ++i) dataset.train.push_back({"view_" + std::to_string(i), cameras[std::size_t(i)], Image{}});
  if (with_points) dataset.points = PointCloud{};
  return dataset;
}

ValidationSettings every(int n) {
  ValidationSettings settings;
  settings.every = n;
  settings.decide_at = 0.5f;
  settings.fall_db = 0.3f;
  return settings;
}

GaussianModel model_of_size(std::size_t n) {
  GaussianModel model;
  model.resize(n);
  return model;
}

bool same_model(const GaussianModel& a, const GaussianModel& b) {
  if (a.sh_degree != b.sh_degree) return false;
  for (const ParameterGroup& group : kParameterGroups)
    if (group.of(a) != group.of(b)) return false;
  return true;
}

// 24 views on a ring 4 units out, two of them photographed twice from almost the same place
// (views 24 and 25), and two close-ups 1.5 units out whose nearest neighbours are far.
TEST(ValidationHoldout, TakesTheMostRedundantViewsNeverTwoNeighboursNorACloseUp) {
  Dataset dataset;
  const auto add_view = [&](float radius, float azimuth) {
    const glm::vec3 eye(radius * std::cos(azimuth), radius * std::sin(azimuth), 1.0f);
    dataset.train.push_back({"view_" + std::to_string(dataset.train.size()),
                             look_at(eye, glm::vec3(0.0f), glm::vec3(0, 0, 1), 20, 20, 16, 16), Image{}});
  };
  const float step = 2.0f * 3.14159265f / 24.0f;
  for (int i = 0; i < 24; ++i) add_view(4.0f, step * float(i));
  add_view(4.0f, step * 5.0f + 0.01f);   // 24: next to 5
  add_view(4.0f, step * 17.0f + 0.01f);  // 25: next to 17
  add_view(1.5f, 0.3f);                  // 26, 27: close-ups
  add_view(1.5f, 3.5f);
  PointCloud points;
  points.positions = {0.1f, 0, 0, -0.1f, 0, 0, 0, 0.1f, 0.2f};
  points.colors.assign(9, 0.5f);

  const std::vector<std::size_t> taken = choose_validation_views(dataset.train, points, 8);
  ASSERT_EQ(taken.size(), 4u);  // ceil(28 / 8)
  const auto took = [&](std::size_t view) { return std::count(taken.begin(), taken.end(), view) == 1; };
  EXPECT_NE(took(5), took(24));  // one of each pair of near-duplicates, the other trains
  EXPECT_NE(took(17), took(25));
  EXPECT_FALSE(took(26));
  EXPECT_FALSE(took(27));
  const glm::vec3 center(0.0f, 0.0f, 0.2f / 3.0f);
  for (std::size_t a : taken)
    for (std::size_t b : taken) {  // no two taken views are neighbours on the ring
      if (a >= b) continue;
      EXPECT_GT(view_distance(dataset.train[a].camera, dataset.train[b].camera, center), 2.5f * step);
    }

  dataset.points = points;
  const ValidationHoldout holdout(dataset, every(8));
  ASSERT_TRUE(holdout.active());
  ASSERT_EQ(holdout.views().size(), taken.size());
  for (std::size_t k = 0; k < taken.size(); ++k) {
    EXPECT_TRUE(holdout.holds_out(taken[k]));
    EXPECT_EQ(holdout.views()[k].name, dataset.train[taken[k]].name);
  }
  EXPECT_FALSE(holdout.holds_out(26));
}

TEST(ValidationHoldout, IsOffWithoutPointsWithoutSettingOrWithOneViewOnly) {
  EXPECT_FALSE(ValidationHoldout(capture(40, false), every(16)).active());  // synthetic data
  EXPECT_FALSE(ValidationHoldout(capture(40, true), every(0)).active());
  EXPECT_FALSE(ValidationHoldout(capture(16, true), every(16)).active());  // view 0 alone
  EXPECT_TRUE(ValidationHoldout(capture(17, true), every(16)).active());
  EXPECT_TRUE(ValidationHoldout(capture(40, true), every(0)).metrics().is_null());
}

TEST(ValidationHoldout, ScoresAtItsIntervalWhileActive) {
  ValidationSettings settings = every(4);
  settings.interval = 250;
  const ValidationHoldout holdout(capture(12, true), settings);
  EXPECT_TRUE(holdout.due(250, 1));
  EXPECT_FALSE(holdout.due(251, 1));
  EXPECT_TRUE(holdout.due(252, 4));  // a batch of views 249..252 holds 250
}

TEST(ValidationHoldout, KeepsTheBestModelAndRestoresItWhenTheMedianOfTheLastThreeFell) {
  ValidationHoldout holdout(capture(12, true), every(4));
  using D = ValidationHoldout::Decision;
  EXPECT_EQ(holdout.record(100, 20.0, model_of_size(1), 0.1), D::kWait);
  // The medians of three (of one and two at the start, the upper one): 20, 22, 21.9, 21.9,
  // 21.8, 21.5 and, last, 21.5.
  EXPECT_EQ(holdout.record(200, 22.0, model_of_size(2), 0.2), D::kWait);  // the best score
  EXPECT_EQ(holdout.record(300, 21.9, model_of_size(3), 0.3), D::kWait);
  EXPECT_EQ(holdout.record(400, 21.8, model_of_size(4), 0.35), D::kWait);
  EXPECT_EQ(holdout.record(500, 21.5, model_of_size(5), 0.4), D::kWait);
  EXPECT_EQ(holdout.record(600, 21.4, model_of_size(6), 0.45), D::kWait);
  EXPECT_EQ(holdout.best_model().size(), 2u);
  EXPECT_EQ(holdout.record(700, 21.6, model_of_size(7), 0.5), D::kRestore);  // 0.5 below 22
  EXPECT_FALSE(holdout.active());
  EXPECT_TRUE(holdout.restored());
  EXPECT_EQ(holdout.best_model().size(), 2u);
  const nlohmann::json m = holdout.metrics();
  EXPECT_EQ(m.at("decision"), "restored");
  EXPECT_EQ(m.at("best").at("iteration"), 200);
  EXPECT_EQ(m.at("decided_at_iteration"), 700);
  EXPECT_NEAR(m.at("fall_measured_db").get<double>(), 0.5, 1e-9);
  EXPECT_EQ(m.at("scores").size(), 7u);
  EXPECT_NE(holdout.restore_summary().find("fell 0.50 dB"), std::string::npos) << holdout.restore_summary();
  EXPECT_NE(holdout.restore_summary().find("model of iteration 200"), std::string::npos);
  // Decided once: later scores change nothing.
  EXPECT_EQ(holdout.record(800, 30.0, model_of_size(8), 0.6), D::kRestore);
  EXPECT_EQ(holdout.metrics().at("scores").size(), 7u);
}

TEST(ValidationHoldout, NeitherASingleDipNorASingleHighScoreIsAFall) {
  using D = ValidationHoldout::Decision;
  const auto decide = [](const std::vector<double>& scores) {
    ValidationHoldout holdout(capture(12, true), every(4));
    for (std::size_t i = 0; i + 1 < scores.size(); ++i)
      EXPECT_EQ(holdout.record(100 * int(i + 1), scores[i], model_of_size(1), 0.1), D::kWait);
    const D decision = holdout.record(100 * int(scores.size()), scores.back(), model_of_size(1), 0.5);
    EXPECT_FALSE(holdout.active());
    EXPECT_FALSE(holdout.holds_out(0));
    return decision;
  };
  EXPECT_EQ(decide({22.0, 21.9, 20.0}), D::kRejoin);         // a dip of 1.9 dB, the last score
  EXPECT_EQ(decide({22.0, 21.9, 20.0, 21.8}), D::kRejoin);   // one dip between two
  // real_thermos after its warm-up: one score 0.4 above its neighbours is not the level.
  EXPECT_EQ(decide({35.78, 36.25, 36.64, 35.95, 36.23}), D::kRejoin);
  EXPECT_EQ(decide({22.0, 23.0}), D::kRejoin);               // rising
  EXPECT_EQ(decide({22.0, 21.0, 21.0}), D::kRestore);        // two low scores are a fall
  EXPECT_EQ(decide({22.0, 22.1, 21.0, 21.0}), D::kRestore);
}

TEST(ValidationHoldout, CheckpointStateRoundTripsAndOldCheckpointsTrainOnEveryView) {
  const Dataset dataset = capture(12, true);
  ValidationHoldout holdout(dataset, every(4));
  holdout.record(100, 20.0, model_of_size(3), 0.1);
  holdout.record(200, 19.0, model_of_size(4), 0.2);
  ASSERT_NE(holdout.checkpoint_model(), nullptr);

  ValidationHoldout loaded(dataset, every(4));
  loaded.checkpoint_state_loaded(holdout.checkpoint_state());
  ASSERT_NE(loaded.checkpoint_model(), nullptr);
  *loaded.checkpoint_model() = *holdout.checkpoint_model();
  loaded.checkpoint_model_loaded(0);
  EXPECT_EQ(loaded.metrics(), holdout.metrics());
  EXPECT_TRUE(loaded.active());
  EXPECT_EQ(loaded.best_model().size(), 3u);

  ValidationHoldout old(dataset, every(4));
  old.checkpoint_state_loaded(nullptr);
  EXPECT_FALSE(old.active());
  EXPECT_FALSE(old.holds_out(0));

  // A checkpoint that holds views out, loaded where the data has none to hold out.
  ValidationHoldout none(capture(12, false), every(4));
  EXPECT_THROW(none.checkpoint_state_loaded(holdout.checkpoint_state()), ArgumentError);

  // A run that held nothing out, resumed where there are views to hold out: it goes on
  // training on every view, as it began.
  ValidationHoldout nothing_held(dataset, every(0));
  ValidationHoldout resumed(dataset, every(4));
  resumed.checkpoint_state_loaded(nothing_held.checkpoint_state());
  EXPECT_FALSE(resumed.active());
  EXPECT_FALSE(resumed.holds_out(0));

  // A decided holdout stays decided; views held out after a decision is a corrupt state.
  holdout.record(300, 17.0, model_of_size(5), 0.5);
  ASSERT_TRUE(holdout.restored());
  ValidationHoldout decided(dataset, every(4));
  decided.checkpoint_state_loaded(holdout.checkpoint_state());
  EXPECT_TRUE(decided.restored());
  EXPECT_FALSE(decided.active());
  EXPECT_EQ(decided.checkpoint_model(), nullptr);
  nlohmann::json corrupt = holdout.checkpoint_state();
  corrupt["active"] = true;
  EXPECT_THROW(ValidationHoldout(dataset, every(4)).checkpoint_state_loaded(corrupt), ArgumentError);
}

// Training photographs all white, validation photographs dark, the points dark and the
// background white: every step fades or whitens the model, so each validation score is below
// the one before, and the holdout must restore the model of its first score and end there.
class FallingCapture : public ::testing::Test {
 protected:
  FallingCapture() {
    OrbitRig rig;
    rig.count = 12;
    rig.width = rig.height = 24;
    const std::vector<Camera> cameras = orbit_cameras(rig);
    for (std::size_t i = 0; i < cameras.size(); ++i)
      dataset.train.push_back({"view_" + std::to_string(i), cameras[i], Image(24, 24, 3, 1.0f)});
    dataset.test = {dataset.train[1]};
    dataset.scene_extent = 1.1f * rig.radius;
    PointCloud points;  // a 10 × 10 × 2 grid over the middle of every view
    for (int i = 0; i < 200; ++i) {
      points.positions.insert(points.positions.end(),
                              {0.2f * float(i % 10) - 0.9f, 0.2f * float(i / 10 % 10) - 0.9f, 0.2f * float(i / 100)});
      points.colors.insert(points.colors.end(), {0.1f, 0.1f, 0.1f});
    }
    dataset.points = points;
    config = splat_training_preset("official");  // on white: each step fades the dark model
    config.iterations = config.position_lr_max_steps = 60;
    config.validation.every = 4;
    for (std::size_t i : choose_validation_views(dataset.train, points, config.validation.every))
      dataset.train[i].image = Image(24, 24, 3, 0.1f);
    config.validation.interval = 5;
    config.validation.decide_at = 0.5f;  // at the first score from iteration 30 on
  }
  Dataset dataset;
  SplatTrainingConfig config;
};

TEST_F(FallingCapture, RestoresTheBestModelAndFinishes) {
  SplatTrainer trainer(dataset, config);
  ASSERT_TRUE(trainer.validation().active());
  while (!trainer.finished() && trainer.iteration() < config.iterations) trainer.step();
  // Scored before the steps holding 5, 10, ...: after 4, 9, ..., 34, the first at or past
  // half of the 60-iteration schedule.
  EXPECT_EQ(trainer.iteration(), 34);
  const nlohmann::json m = trainer.validation().metrics();
  EXPECT_EQ(m.at("decision"), "restored") << m.dump();
  EXPECT_EQ(m.at("best").at("iteration"), 4) << m.dump();

  SplatTrainer four_steps(dataset, config);
  for (int i = 0; i < 4; ++i) four_steps.step();
  EXPECT_TRUE(same_model(trainer.model(), four_steps.model()));
}

TEST_F(FallingCapture, AResumedRunEndsAsAnUninterruptedOne) {
  const auto dir = test::scratch_dir("validation_holdout_resume");
  SplatTrainer whole(dataset, config);
  while (!whole.finished() && whole.iteration() < config.iterations) whole.step();

  SplatTrainer first(dataset, config);
  for (int i = 0; i < 12; ++i) first.step();  // scored after 4 and 9: a best model to keep
  first.save_checkpoint(dir / "mid.ckpt");
  SplatTrainer resumed(dataset, config);
  resumed.load_checkpoint(dir / "mid.ckpt");
  while (!resumed.finished() && resumed.iteration() < config.iterations) resumed.step();
  EXPECT_EQ(resumed.iteration(), whole.iteration());
  EXPECT_TRUE(same_model(resumed.model(), whole.model()));
  EXPECT_EQ(resumed.validation().metrics(), whole.validation().metrics());

  // A checkpoint of the finished run loads finished.
  whole.save_checkpoint(dir / "end.ckpt");
  SplatTrainer reloaded(dataset, config);
  reloaded.load_checkpoint(dir / "end.ckpt");
  EXPECT_TRUE(reloaded.finished());
  EXPECT_TRUE(same_model(reloaded.model(), whole.model()));
}

}  // namespace
}  // namespace splat
