#pragma once
// The limits both trainers' settings share (docs/DESIGN.md §4.7): far beyond any real run,
// they rule out values that would overflow a counter, stop a run from ever ending, or
// allocate without bound. Each config's table (training_config.cpp,
// nerf_training_config.cpp) gives every key one of these ranges or its own.
#include "splat/core/setting_value.hpp"

namespace splat {

constexpr int kMaxTrainingIterations = 10'000'000;
constexpr double kMaxTrainingSeconds = 30.0 * 24 * 3600;  // 30 days
constexpr double kMaxLearningRate = 1.0;

namespace setting_ranges {

constexpr SettingRange kUnit{0, 1};
constexpr SettingRange kSeed{0, 4294967295.0};
constexpr SettingRange kSeconds{0, kMaxTrainingSeconds};
// A number of iterations, or an iteration (0 = never, or the start).
constexpr SettingRange kIterations{0, kMaxTrainingIterations};
// What a run or an interval divides by: at least one iteration.
constexpr SettingRange kPositiveIterations{1, kMaxTrainingIterations};
constexpr SettingRange kRate{0, kMaxLearningRate};
// Rates and factors a log-linear schedule interpolates between: log(0) is not a rate.
constexpr SettingRange kLogScheduleRate{1e-12, kMaxLearningRate};
constexpr SettingRange kLogScheduleFactor{1e-6, 1};
// Opacities a logit is taken of: 0 and 1 have none.
constexpr SettingRange kOpacity{1e-6, 0.999999};

}  // namespace setting_ranges

}  // namespace splat
