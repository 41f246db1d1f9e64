// The training config's schedules and its JSON round trip for the appearance-rate decay.
#include <gtest/gtest.h>

#include <cmath>

#include "splat/train/training_config.hpp"

namespace splat {
namespace {

TEST(AppearanceLrFactor, ConstantUnlessAFinalFactorIsSet) {
  const SplatTrainingConfig config = splat_training_preset("compact");
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

}  // namespace
}  // namespace splat
