// Position steps that grow with distance beyond the cameras.
#include "splat/optim/far_steps.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "splat/core/error.hpp"

namespace splat {
namespace {

TEST(FarSteps, StepsBeyondTheDistanceGrowAsAPowerOfIt) {
  const FarSteps far{glm::vec3(1, 0, 0), 4.0f, 40.0f, 3.0f};
  // One Gaussian inside D (r = 2), one on it, one at 3·D (r = 12), one at 10·D (the limit)
  // and one beyond the limit.
  const std::vector<float> before = {3, 0, 0, 1, 4, 0, 1, 0, -12, 41, 0, 0, 1, 400, 0};
  std::vector<float> means = {3.1f, 0.2f, -0.3f, 1.5f, 4, 0, 1.01f, 0, -12, 41, 0.001f, 0, 1, 400.25f, 0};
  const std::vector<float> stepped = means;
  scale_far_steps(means, before, far);
  for (int k = 0; k < 6; ++k) EXPECT_EQ(means[k], stepped[k]);  // within D: bit for bit
  EXPECT_NEAR(means[6], 1.0f + 27.0f * 0.01f, 1e-5f);           // (12 / 4)³ = 27
  EXPECT_EQ(means[7], 0.0f);
  EXPECT_EQ(means[8], -12.0f);
  EXPECT_NEAR(means[10], 1000.0f * 0.001f, 1e-4f);              // (40 / 4)³ = 1000
  EXPECT_FLOAT_EQ(means[13], 400.0f + 1000.0f * 0.25f);           // held at the limit's 1000
}

TEST(FarSteps, OffLeavesEveryStepAndSizesAreChecked) {
  const std::vector<float> before = {0, 0, 50};
  std::vector<float> means = {0, 0, 51};
  scale_far_steps(means, before, FarSteps{glm::vec3(0.0f), 4.0f, 40.0f, 0.0f});
  scale_far_steps(means, before, FarSteps{glm::vec3(0.0f), 0.0f, 40.0f, 3.0f});
  EXPECT_EQ(means[2], 51.0f);
  EXPECT_THROW(scale_far_steps(means, before, FarSteps{glm::vec3(0.0f), 4.0f, 2.0f, 3.0f}), ArgumentError);
  std::vector<float> short_means = {0, 0};
  EXPECT_THROW(scale_far_steps(short_means, std::vector<float>{0, 0}, FarSteps{}), ArgumentError);
  EXPECT_THROW(scale_far_steps(means, std::vector<float>{0, 0, 0, 1, 1, 1}, FarSteps{}), ArgumentError);
}

}  // namespace
}  // namespace splat
