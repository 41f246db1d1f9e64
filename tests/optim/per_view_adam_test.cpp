// PerViewAdam: each view's block steps on its own, each part at its own rate, exactly as a
// FlatAdam of that part would; its checkpoint state restores exactly and is checked.
#include "splat/optim/per_view_adam.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "splat/core/error.hpp"

namespace splat {
namespace {

constexpr FlatAdamSettings kSettings{0.9, 0.999, 1e-8};

TEST(PerViewAdam, StepsOneViewsPartsAsSeparateAdamsAtTheirOwnRates) {
  PerViewAdam adam(3, {2, 1}, kSettings, "test state");
  FlatAdam first(2, kSettings), second(1, kSettings);
  std::vector<float> expected_first(2, 0.0f), expected_second(1, 0.0f);
  for (int i = 0; i < 5; ++i) {
    const float grad[] = {0.5f + float(i), -2.0f, 0.25f * float(i + 1)};
    const float rates[] = {1e-2f, 3e-3f};
    adam.step(1, grad, rates);
    first.step(expected_first, {grad, 2}, 1e-2f);
    second.step(expected_second, {grad + 2, 1}, 3e-3f);
  }
  EXPECT_EQ(adam.parameters(1)[0], expected_first[0]);
  EXPECT_EQ(adam.parameters(1)[1], expected_first[1]);
  EXPECT_EQ(adam.parameters(1)[2], expected_second[0]);
  for (std::size_t view : {0u, 2u})
    for (float p : adam.parameters(view)) EXPECT_EQ(p, 0.0f) << "view " << view << " moved";
  EXPECT_EQ(adam.steps(), (std::vector<long long>{0, 5, 0}));
}

TEST(PerViewAdam, RestoresItsCheckpointStateExactly) {
  PerViewAdam adam(2, {2, 1}, kSettings, "test state");
  const float grad[] = {1.0f, -1.0f, 0.5f}, rates[] = {1e-2f, 1e-3f};
  adam.step(0, grad, rates);
  adam.step(1, grad, rates);
  adam.step(1, grad, rates);
  PerViewAdam restored(2, {2, 1}, kSettings, "test state");
  restored.restore(adam.parameters(), adam.first_moments(), adam.second_moments(), adam.steps());
  adam.step(1, grad, rates);
  restored.step(1, grad, rates);
  EXPECT_EQ(restored.parameters(), adam.parameters());
  EXPECT_EQ(restored.first_moments(), adam.first_moments());
  EXPECT_EQ(restored.second_moments(), adam.second_moments());
  EXPECT_EQ(restored.steps(), adam.steps());
}

TEST(PerViewAdam, RejectsStateOfTheWrongSizeOrNotFinite) {
  PerViewAdam adam(2, {3}, kSettings, "test state");
  const std::vector<float> six(6, 0.0f), five(5, 0.0f);
  const std::vector<long long> steps{1, 1};
  EXPECT_THROW(adam.restore(five, six, six, steps), ArgumentError);
  EXPECT_THROW(adam.restore(six, six, six, {1}), ArgumentError);
  EXPECT_THROW(adam.restore(six, six, six, {1, -1}), ArgumentError);
  std::vector<float> nan = six;
  nan[4] = std::numeric_limits<float>::quiet_NaN();
  try {
    adam.restore(six, nan, six, steps);
    FAIL() << "a NaN moment was accepted";
  } catch (const ArgumentError& e) {
    EXPECT_NE(std::string(e.what()).find("test state"), std::string::npos) << e.what();
  }
  const float grad[] = {1.0f, 2.0f}, rates[] = {1e-3f};
  EXPECT_THROW(adam.step(0, grad, rates), ArgumentError);  // 2 gradients for a block of 3
}

}  // namespace
}  // namespace splat
