#include "splat/gaussians/initialization.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "splat/core/error.hpp"
#include "splat/core/spherical_harmonics.hpp"
#include "splat/gaussians/nearest_neighbors.hpp"

namespace splat {
namespace {

constexpr int kK = 3;

// 2000 points: a uniform cube, a tight cluster, points on a plane (many equal coordinates
// along one axis) and exact duplicates, so the tree meets every awkward case.
std::vector<float> awkward_cloud(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> p;
  for (int i = 0; i < 1000; ++i)
    for (int a = 0; a < 3; ++a) p.push_back(5.0f * u(rng));
  for (int i = 0; i < 600; ++i)
    for (int a = 0; a < 3; ++a) p.push_back(2.0f + 0.01f * u(rng));
  for (int i = 0; i < 380; ++i) {
    p.push_back(u(rng));
    p.push_back(-3.0f);
    p.push_back(u(rng));
  }
  for (int i = 0; i < 20; ++i)  // duplicates of earlier points
    for (int a = 0; a < 3; ++a) p.push_back(p[std::size_t(37 * i) * 3 + a]);
  return p;
}

struct BruteForce {
  std::vector<float> mean;                  // [P]
  std::vector<std::vector<float>> nearest;  // [P][k] ascending squared distances
};

BruteForce brute_force(const std::vector<float>& p) {
  const std::size_t n = p.size() / 3;
  BruteForce out{std::vector<float>(n), std::vector<std::vector<float>>(n)};
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<float> d;
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      const float dx = p[3 * j] - p[3 * i], dy = p[3 * j + 1] - p[3 * i + 1],
                  dz = p[3 * j + 2] - p[3 * i + 2];
      d.push_back(dx * dx + dy * dy + dz * dz);
    }
    std::partial_sort(d.begin(), d.begin() + kK, d.end());
    d.resize(kK);
    out.nearest[i] = d;
    out.mean[i] = (d[0] + d[1] + d[2]) / 3.0f;
  }
  return out;
}

float squared_distance(const std::vector<float>& p, std::size_t a, std::size_t b) {
  const float dx = p[3 * a] - p[3 * b], dy = p[3 * a + 1] - p[3 * b + 1],
              dz = p[3 * a + 2] - p[3 * b + 2];
  return dx * dx + dy * dy + dz * dz;
}

TEST(NearestNeighbours, MatchBruteForceExactly) {
  const std::vector<float> p = awkward_cloud(5);
  const std::size_t n = p.size() / 3;
  ASSERT_EQ(n, 2000u);
  std::vector<std::uint32_t> found;
  const std::vector<float> mean = mean_squared_neighbour_distance(p, kK, &found);
  const BruteForce truth = brute_force(p);
  ASSERT_EQ(mean.size(), n);
  ASSERT_EQ(found.size(), n * kK);
  for (std::size_t i = 0; i < n; ++i) {
    SCOPED_TRACE(testing::Message() << "point " << i);
    // The neighbours found are other points, and their distances are exactly the k smallest
    // (ties may pick different but equally near points). FLOAT_EQ's 4 ulps only allow for
    // the compiler fusing multiply-adds differently here and in the library; a wrong
    // neighbour is off by far more.
    for (int j = 0; j < kK; ++j) {
      const std::uint32_t q = found[i * kK + j];
      ASSERT_LT(q, n);
      EXPECT_NE(q, i);
      EXPECT_FLOAT_EQ(squared_distance(p, i, q), truth.nearest[i][j]);
    }
    EXPECT_FLOAT_EQ(mean[i], truth.mean[i]);
  }
}

TEST(NearestNeighbours, DuplicatesAreAtDistanceZero) {
  std::vector<float> p = {0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 3};
  const std::vector<float> mean = mean_squared_neighbour_distance(p, kK);
  EXPECT_FLOAT_EQ(mean[0], (0.0f + 1.0f + 4.0f) / 3.0f);
  EXPECT_FLOAT_EQ(mean[1], (0.0f + 1.0f + 4.0f) / 3.0f);
  EXPECT_FLOAT_EQ(mean[4], (9.0f + 9.0f + 10.0f) / 3.0f);
}

TEST(NearestNeighbours, FewerPointsThanNeighbours) {
  EXPECT_EQ(mean_squared_neighbour_distance({1, 2, 3}, kK), std::vector<float>{0.0f});
  const std::vector<float> two = mean_squared_neighbour_distance({0, 0, 0, 0, 3, 4}, kK);
  EXPECT_EQ(two, (std::vector<float>{25.0f, 25.0f}));
  EXPECT_TRUE(mean_squared_neighbour_distance({}, kK).empty());
  EXPECT_THROW(mean_squared_neighbour_distance({1, 2}, kK), ArgumentError);
  EXPECT_THROW(mean_squared_neighbour_distance({1, 2, 3}, 0), ArgumentError);
}

TEST(NearestNeighbours, SameForAnyThreadCount) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> p(3 * 50000);
  for (float& x : p) x = u(rng);
  auto run = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    std::vector<std::uint32_t> neighbours;
    std::vector<float> mean = mean_squared_neighbour_distance(p, kK, &neighbours);
    return std::pair{mean, neighbours};
  };
  EXPECT_EQ(run(1), run(4));
}

TEST(Initialization, FromPointsFollowsTheOfficialFormulas) {
  PointCloud cloud;
  cloud.positions = awkward_cloud(8);
  const std::size_t n = cloud.size();
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (std::size_t i = 0; i < 3 * n; ++i) cloud.colors.push_back(u(rng));

  const GaussianModel m = initialize_from_points(cloud, 3);
  ASSERT_EQ(m.size(), n);
  EXPECT_NO_THROW(m.check_consistent());
  EXPECT_EQ(m.means, cloud.positions);
  const BruteForce truth = brute_force(cloud.positions);
  const std::size_t row = 48;
  const float logit = std::log(0.1f / 0.9f);
  for (std::size_t i = 0; i < n; ++i) {
    SCOPED_TRACE(testing::Message() << "Gaussian " << i);
    const float scale = std::sqrt(std::max(truth.mean[i], 1e-7f));
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(m.log_scales[3 * i + a], std::log(scale), 1e-5);
    EXPECT_EQ(m.quats[4 * i], 1.0f);
    EXPECT_EQ(m.quats[4 * i + 1], 0.0f);
    EXPECT_EQ(m.quats[4 * i + 2], 0.0f);
    EXPECT_EQ(m.quats[4 * i + 3], 0.0f);
    EXPECT_FLOAT_EQ(m.opacity_logits[i], logit);
    for (int c = 0; c < 3; ++c) {
      // The DC band renders back the point's colour: C0·dc + 0.5.
      const float dc = m.sh[i * row + c];
      EXPECT_NEAR(float(kShC0) * dc + 0.5f, cloud.colors[3 * i + c], 1e-6);
    }
    for (std::size_t k = 3; k < row; ++k) EXPECT_EQ(m.sh[i * row + k], 0.0f);
  }
}

TEST(Initialization, CoincidentPointsGetTheFloorScale) {
  PointCloud cloud;
  cloud.positions = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 5, 5, 5};
  cloud.colors.assign(cloud.positions.size(), 0.5f);
  const GaussianModel m = initialize_from_points(cloud, 0);
  EXPECT_FLOAT_EQ(m.log_scales[0], std::log(std::sqrt(1e-7f)));  // three others at 0
  EXPECT_GT(m.log_scales[3 * 4], 1.0f);                           // the far point
  EXPECT_EQ(m.sh[0], 0.0f);                                       // grey is DC 0
}

TEST(Initialization, FromPointsRejectsBadClouds) {
  EXPECT_THROW(initialize_from_points(PointCloud{}, 3), ArgumentError);
  PointCloud mismatched;
  mismatched.positions = {0, 0, 0, 1, 1, 1};
  mismatched.colors = {0.5f, 0.5f, 0.5f};
  EXPECT_THROW(initialize_from_points(mismatched, 3), ArgumentError);
  PointCloud fine;
  fine.positions = {0, 0, 0};
  fine.colors = {0.5f, 0.5f, 0.5f};
  EXPECT_THROW(initialize_from_points(fine, 4), ArgumentError);
  EXPECT_EQ(initialize_from_points(fine, 0).size(), 1u);
}

TEST(Initialization, RandomFillsTheCubeWithDarkGrey) {
  const std::size_t count = 20000;
  const GaussianModel m = initialize_random(count, kRandomInitHalfExtent, 42, 3);
  ASSERT_EQ(m.size(), count);
  EXPECT_NO_THROW(m.check_consistent());
  float low[3] = {1e9f, 1e9f, 1e9f}, high[3] = {-1e9f, -1e9f, -1e9f};
  double sum[3] = {0, 0, 0};
  for (std::size_t i = 0; i < count; ++i)
    for (int a = 0; a < 3; ++a) {
      const float x = m.means[3 * i + a];
      ASSERT_GE(x, -1.3f);
      ASSERT_LT(x, 1.3f);
      low[a] = std::min(low[a], x);
      high[a] = std::max(high[a], x);
      sum[a] += x;
    }
  for (int a = 0; a < 3; ++a) {  // spread over the whole cube, centred
    EXPECT_LT(low[a], -1.29f);
    EXPECT_GT(high[a], 1.29f);
    EXPECT_NEAR(sum[a] / count, 0.0, 0.03);
  }
  const std::size_t row = 48;
  double dc_sum = 0;
  for (std::size_t i = 0; i < count; ++i) {
    for (int c = 0; c < 3; ++c) {
      const float dc = m.sh[i * row + c];
      ASSERT_GE(dc, 0.0f);
      ASSERT_LT(dc, 1.0f / 255.0f);
      dc_sum += dc;
    }
    for (std::size_t k = 3; k < row; ++k) ASSERT_EQ(m.sh[i * row + k], 0.0f);
  }
  EXPECT_NEAR(dc_sum / (3.0 * count), 0.5 / 255.0, 0.02 / 255.0);
  // Scales come from the neighbour distances of these positions.
  const std::vector<float> d2 = mean_squared_neighbour_distance(m.means, 3);
  for (std::size_t i = 0; i < count; i += 97)
    EXPECT_FLOAT_EQ(m.log_scales[3 * i + 2], std::log(std::sqrt(std::max(d2[i], 1e-7f))));
}

TEST(Initialization, RandomIsDeterministicPerSeed) {
  const GaussianModel a = initialize_random(500, 1.3f, 7, 1);
  const GaussianModel b = initialize_random(500, 1.3f, 7, 1);
  const GaussianModel c = initialize_random(500, 1.3f, 8, 1);
  EXPECT_EQ(a.means, b.means);
  EXPECT_EQ(a.sh, b.sh);
  EXPECT_EQ(a.log_scales, b.log_scales);
  EXPECT_NE(a.means, c.means);
  EXPECT_THROW(initialize_random(0, 1.3f, 7, 1), ArgumentError);
  EXPECT_THROW(initialize_random(10, 0.0f, 7, 1), ArgumentError);
}

TEST(Initialization, EvenSubsampleKeepsEveryKthPointWithItsColour) {
  PointCloud cloud;
  for (int i = 0; i < 10; ++i)
    for (int k = 0; k < 3; ++k) {
      cloud.positions.push_back(float(i));
      cloud.colors.push_back(float(i) / 10);
    }
  const PointCloud kept = evenly_subsampled(cloud, 4);  // points 0, 2, 5, 7
  ASSERT_EQ(kept.size(), 4u);
  const float expected[] = {0, 2, 5, 7};
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(kept.positions[3 * i + 1], expected[i]);
    EXPECT_FLOAT_EQ(kept.colors[3 * i + 2], expected[i] / 10);
  }
  EXPECT_EQ(evenly_subsampled(cloud, 10).positions, cloud.positions);
  EXPECT_EQ(evenly_subsampled(cloud, 50).size(), 10u);
}

}  // namespace
}  // namespace splat
