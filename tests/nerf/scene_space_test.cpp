// Where the NeRF samples: a bounded scene exactly as the box sampler, an unbounded one with
// the space outside its box contracted into [−2, 2]³ and samples out to the far distance.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "splat/core/error.hpp"
#include "splat/nerf/samplers.hpp"
#include "splat/nerf/scene_space.hpp"

namespace splat {
namespace {

const AxisAlignedBox kBox{glm::vec3(-1.0f, -2.0f, 0.0f), glm::vec3(3.0f, 2.0f, 2.0f)};  // centre (1, 0, 1)

float linf(const glm::vec3& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

TEST(NerfSceneSpace, BoundedIsTheBoxSamplerInWorldCoordinates) {
  const SceneSpace space{kBox, false};
  EXPECT_EQ(space.to_network(glm::vec3(7.0f, -3.0f, 2.5f)), glm::vec3(7.0f, -3.0f, 2.5f));
  EXPECT_EQ(space.network_box().lo, kBox.lo);
  EXPECT_EQ(space.network_box().hi, kBox.hi);
  const Ray ray{glm::vec3(-5.0f, 0.1f, 1.0f), glm::normalize(glm::vec3(1.0f, 0.05f, 0.02f))};
  std::vector<float> t(16), delta(16), t_ref(16), delta_ref(16);
  std::mt19937 rng(3), rng_ref(3);
  ASSERT_TRUE(space.place_samples(ray, 0.05f, true, rng, t, delta));
  stratified_samples(*intersect_box(ray, kBox, 0.05f), true, rng_ref, t_ref, delta_ref);
  EXPECT_EQ(t, t_ref);
  EXPECT_EQ(delta, delta_ref);
  const Ray miss{glm::vec3(-5.0f, 10.0f, 1.0f), glm::vec3(1.0f, 0.0f, 0.0f)};
  EXPECT_FALSE(space.place_samples(miss, 0.05f, true, rng, t, delta));
}

TEST(NerfSceneSpace, ContractionKeepsTheBoxAndFoldsTheRestIntoTheShell) {
  const SceneSpace space{kBox, true};
  EXPECT_EQ(space.network_box().lo, glm::vec3(-2.0f));
  EXPECT_EQ(space.network_box().hi, glm::vec3(2.0f));
  // Inside the box: the box normalised to [−1, 1]³.
  EXPECT_NEAR(space.to_network(glm::vec3(3.0f, 0.0f, 1.0f)).x, 1.0f, 1e-6f);
  EXPECT_NEAR(space.to_network(glm::vec3(0.0f, 1.0f, 1.5f)).y, 0.5f, 1e-6f);
  EXPECT_NEAR(space.to_network(glm::vec3(0.0f, 1.0f, 1.5f)).z, 0.5f, 1e-6f);
  // Continuous across the box's face, monotone outwards, and never past the shell.
  const glm::vec3 just_outside = space.to_network(glm::vec3(3.0001f, 0.0f, 1.0f));
  EXPECT_NEAR(just_outside.x, 1.0f, 1e-3f);
  float previous = 0.0f;
  for (float x = 1.0f; x < 1e6f; x *= 1.5f) {
    const glm::vec3 p = space.to_network(glm::vec3(1.0f + 2.0f * x, 0.3f, 1.2f));
    EXPECT_LE(linf(p), 2.0f);
    EXPECT_GT(p.x, previous);
    previous = p.x;
  }
  EXPECT_GT(previous, 1.999f);
  // At ‖u‖∞ = 4 the contraction gives 2 − 1/4 along the same direction.
  const glm::vec3 p = space.to_network(glm::vec3(1.0f + 2.0f * 4.0f, 2.0f * 2.0f, 1.0f));
  EXPECT_NEAR(p.x, 1.75f, 1e-5f);
  EXPECT_NEAR(p.y, 0.875f, 1e-5f);
}

TEST(NerfSceneSpace, UnboundedRaysSampleTheBoxEvenlyThenTheFarEvenlyInDisparity) {
  const SceneSpace space{kBox, true};
  const Ray ray{glm::vec3(1.0f, 0.0f, 1.0f), glm::vec3(0.0f, 1.0f, 0.0f)};  // from the centre, leaves at t = 2
  std::vector<float> t(8), delta(8);
  std::mt19937 rng(0);
  ASSERT_TRUE(space.place_samples(ray, 0.1f, false, rng, t, delta));
  const float far = kUnboundedFarFactor * 2.0f;  // the largest half-size is 2
  // Four bin midpoints in [0.1, 2], then four in disparity from 1/2 to 1/far.
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(t[i], 0.1f + (i + 0.5f) * 1.9f / 4.0f, 1e-5f) << i;
  for (int i = 0; i < 4; ++i) {
    const float s = (i + 0.5f) / 4.0f;
    EXPECT_NEAR(1.0f / t[4 + i], 0.5f + s * (1.0f / far - 0.5f), 1e-6f) << i;
  }
  for (int i = 0; i + 1 < 8; ++i) EXPECT_NEAR(delta[i], t[i + 1] - t[i], 1e-4f * t[i + 1]);
  EXPECT_NEAR(t[7] + delta[7], far, 1e-3f * far);  // the last interval reaches the far distance

  // Jittered: sorted, and every sample's point inside the contracted space.
  for (unsigned seed = 0; seed < 20; ++seed) {
    std::mt19937 jitter_rng(seed);
    const Ray oblique{glm::vec3(0.5f, -1.0f, 0.5f), glm::normalize(glm::vec3(0.3f, -1.0f, 0.7f))};
    ASSERT_TRUE(space.place_samples(oblique, 0.1f, true, jitter_rng, t, delta));
    EXPECT_TRUE(std::is_sorted(t.begin(), t.end()));
    EXPECT_GE(t.front(), 0.1f);
    for (std::size_t i = 0; i < t.size(); ++i) {
      EXPECT_GE(delta[i], 0.0f);
      EXPECT_LE(linf(space.to_network(oblique.origin + t[i] * oblique.direction)), 2.0f);
    }
  }
  // A ray that never meets the box samples the far part only.
  const Ray outside{glm::vec3(20.0f, 0.0f, 1.0f), glm::vec3(1.0f, 0.0f, 0.0f)};
  ASSERT_TRUE(space.place_samples(outside, 0.1f, false, rng, t, delta));
  EXPECT_NEAR(1.0f / t[0], 1.0f / 0.1f + (0.5f / 8.0f) * (1.0f / far - 1.0f / 0.1f), 1e-3f);

  std::vector<float> short_delta(7);
  EXPECT_THROW(space.place_samples(ray, 0.1f, false, rng, t, short_delta), ArgumentError);
}

}  // namespace
}  // namespace splat
