// The training config's schedules and the JSON round trip of their settings.
#include <gtest/gtest.h>

#include <cmath>

#include "splat/train/training_config.hpp"

namespace splat {
namespace {

TEST(AppearanceLrFactor, ConstantUnlessAFinalFactorIsSet) {
  const SplatTrainingConfig config = splat_training_preset("official");
  for (double iteration : {0.0, 1000.0, 30000.0, 90000.0})
    EXPECT_EQ(appearance_lr_factor(config, iteration), 1.0f);
}

TEST(AppearanceLrFactor, DecaysLogLinearlyFromItsStartToTheEndOfThePositionSchedule) {
  SplatTrainingConfig config;
  config.position_lr_max_steps = 42000;
  config.appearance_lr_decay_from = 21000;
  config.appearance_lr_final_factor = 0.1f;
  EXPECT_EQ(appearance_lr_factor(config, 0), 1.0f);
  EXPECT_EQ(appearance_lr_factor(config, 21000), 1.0f);
  EXPECT_NEAR(appearance_lr_factor(config, 31500), std::sqrt(0.1), 1e-6);  // half-way
  EXPECT_NEAR(appearance_lr_factor(config, 42000), 0.1, 1e-7);
  EXPECT_NEAR(appearance_lr_factor(config, 60000), 0.1, 1e-7);  // held after the schedule
}

TEST(AppearanceLrFactor, SettingsSurviveTheConfigFile) {
  SplatTrainingConfig config = splat_training_preset("compact");
  config.appearance_lr_final_factor = 0.25f;
  config.appearance_lr_decay_from = 12345;
  SplatTrainingConfig read = splat_training_preset("official");
  from_json(to_json(config), read);
  EXPECT_EQ(read.appearance_lr_final_factor, 0.25f);
  EXPECT_EQ(read.appearance_lr_decay_from, 12345);
}

TEST(ScheduleIteration, IsTheIterationUnlessTheScheduleFollowsTheBudget) {
  SplatTrainingConfig config = splat_training_preset("official");
  config.iterations = 7000;
  for (int iteration : {1, 3500, 7000}) {
    EXPECT_EQ(schedule_iteration(config, iteration, 0.0), iteration);
    EXPECT_EQ(schedule_iteration(config, iteration, 0.9), iteration);  // a time budget changes nothing
  }
}

TEST(ScheduleIteration, SpansTheRunsIterations) {
  SplatTrainingConfig config = splat_training_preset("compact");
  config.position_lr_max_steps = 50000;
  config.iterations = 7000;  // shorter than the schedule: compressed
  EXPECT_DOUBLE_EQ(schedule_iteration(config, 3500, 0.0), 25000.0);
  EXPECT_DOUBLE_EQ(schedule_iteration(config, 7000, 0.0), 50000.0);
  config.iterations = 100000;  // longer: stretched
  EXPECT_DOUBLE_EQ(schedule_iteration(config, 50000, 0.0), 25000.0);
  config.schedule_iterations = 200000;  // an explicit span overrides the run's iterations
  EXPECT_DOUBLE_EQ(schedule_iteration(config, 50000, 0.0), 12500.0);
}

TEST(ScheduleIteration, FollowsTheTimeBudgetWhenThatIsFurtherAlong) {
  SplatTrainingConfig config = splat_training_preset("compact");
  config.position_lr_max_steps = 50000;
  config.iterations = 50000;
  EXPECT_DOUBLE_EQ(schedule_iteration(config, 1000, 0.5), 25000.0);   // time is further along
  EXPECT_DOUBLE_EQ(schedule_iteration(config, 30000, 0.5), 30000.0);  // iterations are
  EXPECT_DOUBLE_EQ(schedule_iteration(config, 1000, 1.0), 50000.0);
}

TEST(ScheduleIteration, SettingsSurviveTheConfigFile) {
  SplatTrainingConfig config = splat_training_preset("official");
  config.schedule_follows_budget = true;
  config.schedule_iterations = 4321;
  SplatTrainingConfig read = splat_training_preset("compact");
  from_json(to_json(config), read);
  EXPECT_TRUE(read.schedule_follows_budget);
  EXPECT_EQ(read.schedule_iterations, 4321);
}

}  // namespace
}  // namespace splat
