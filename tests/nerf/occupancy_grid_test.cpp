// The occupancy grid: a density that lives in a sphere marks the sphere's cells, samples
// elsewhere are dropped, the decay rule, determinism.
#include <gtest/gtest.h>

#include <random>
#include <tbb/global_control.h>
#include <vector>

#include "splat/core/error.hpp"
#include "splat/nerf/occupancy_grid.hpp"
#include "splat/nerf/samplers.hpp"

namespace splat {
namespace {

const AxisAlignedBox kBox{glm::vec3(-1.0f), glm::vec3(1.0f)};
const glm::vec3 kSphereCentre(0.2f, -0.1f, 0.0f);
constexpr float kSphereRadius = 0.5f;

// σ = 10 inside the sphere, 0 outside. Counts how many points it was asked about.
struct SphereDensity {
  std::size_t* calls;
  void operator()(std::span<const glm::vec3> points, std::span<float> sigmas) const {
    for (std::size_t i = 0; i < points.size(); ++i)
      sigmas[i] = glm::length(points[i] - kSphereCentre) < kSphereRadius ? 10.0f : 0.0f;
    *calls += points.size();
  }
};

// Distance from the sphere centre to the nearest and farthest points of a cell.
void cell_distances(const OccupancyGrid& grid, std::size_t cell, float& nearest, float& farthest) {
  const glm::vec3 half(0.5f * (kBox.hi - kBox.lo) / float(grid.resolution()));
  const glm::vec3 centre = grid.cell_center(cell);
  const glm::vec3 d = glm::abs(centre - kSphereCentre);
  nearest = glm::length(glm::max(d - half, glm::vec3(0.0f)));
  farthest = glm::length(d + half);
}

TEST(NerfOccupancy, EveryCellIsOccupiedBeforeTheFirstUpdate) {
  const OccupancyGrid grid(kBox, 16);
  EXPECT_EQ(grid.occupied_count(), grid.cell_count());
  EXPECT_EQ(grid.cell_count(), 16u * 16u * 16u);
  EXPECT_TRUE(grid.occupied(glm::vec3(0.9f, -0.9f, 0.3f)));
  EXPECT_TRUE(grid.occupied(kBox.hi));                         // the upper faces are inside
  EXPECT_FALSE(grid.occupied(glm::vec3(1.1f, 0.0f, 0.0f)));  // outside the box: empty
}

TEST(NerfOccupancy, SphereDensityMarksExactlyTheSphereCells) {
  OccupancyGrid grid(kBox, 32);
  std::size_t calls = 0;
  std::mt19937 rng(1);
  // At cell centres: occupied exactly where the centre is inside the sphere.
  grid.update(SphereDensity{&calls}, rng, {.decay = 0.95f, .jitter = false, .cells = 0});
  EXPECT_EQ(calls, grid.cell_count());
  std::size_t inside = 0;
  for (std::size_t c = 0; c < grid.cell_count(); ++c) {
    const bool centre_inside = glm::length(grid.cell_center(c) - kSphereCentre) < kSphereRadius;
    EXPECT_EQ(grid.cell_occupied(c), centre_inside) << c;
    inside += centre_inside;
  }
  EXPECT_EQ(grid.occupied_count(), inside);
  EXPECT_GT(inside, 1000u);  // about 4/3·π·0.5³ / (2/32)³ ≈ 2145 cells
  EXPECT_TRUE(grid.occupied(kSphereCentre));
  EXPECT_FALSE(grid.occupied(glm::vec3(-0.9f, 0.9f, 0.9f)));
}

TEST(NerfOccupancy, JitteredUpdateMarksCellsInsideAndClearsCellsOutside) {
  OccupancyGrid grid(kBox, 24);
  std::size_t calls = 0;
  std::mt19937 rng(2);
  grid.update(SphereDensity{&calls}, rng);  // jittered points, all cells
  for (std::size_t c = 0; c < grid.cell_count(); ++c) {
    float nearest, farthest;
    cell_distances(grid, c, nearest, farthest);
    if (farthest < kSphereRadius) {
      EXPECT_TRUE(grid.cell_occupied(c)) << c;  // wholly inside
    }
    if (nearest > kSphereRadius) {
      EXPECT_FALSE(grid.cell_occupied(c)) << c;  // wholly outside
    }
  }
}

TEST(NerfOccupancy, DropsSamplesInEmptyCellsAndKeepsTheirLengths) {
  OccupancyGrid grid(kBox, 32);
  std::size_t calls = 0;
  std::mt19937 rng(3);
  grid.update(SphereDensity{&calls}, rng, {.decay = 0.95f, .jitter = false, .cells = 0});
  // A ray along x through the sphere.
  const Ray ray{glm::vec3(-3.0f, kSphereCentre.y, kSphereCentre.z), glm::vec3(1, 0, 0)};
  const auto bounds = intersect_box(ray, kBox);
  ASSERT_TRUE(bounds.has_value());
  const int n = 128;
  std::vector<float> t(n), delta(n);
  stratified_samples(*bounds, true, rng, t, delta);
  const std::vector<float> t0 = t, delta0 = delta;
  const std::size_t kept = drop_empty_samples(grid, SceneSpace{kBox}, ray, t, delta);
  // The ray crosses the sphere through its centre: a chord of 1 out of 2 in the box, so
  // about half the samples stay (give or take the cells at the sphere's edge).
  EXPECT_GT(kept, 54u);
  EXPECT_LT(kept, 74u);
  // The kept samples are exactly the occupied ones, in order, each with its own δ.
  std::size_t k = 0;
  for (int i = 0; i < n; ++i) {
    if (!grid.occupied(ray.origin + t0[i] * ray.direction)) continue;
    ASSERT_LT(k, kept);
    EXPECT_EQ(t[k], t0[i]);
    EXPECT_EQ(delta[k], delta0[i]);
    ++k;
  }
  EXPECT_EQ(k, kept);
  for (std::size_t i = 0; i < kept; ++i)
    EXPECT_LT(glm::length(ray.origin + t[i] * ray.direction - kSphereCentre), kSphereRadius + 0.1f);
}

// A field fainter than the threshold everywhere (early training) does not empty the grid:
// the threshold falls to the mean value, so the denser cells stay.
TEST(NerfOccupancy, FaintFieldKeepsItsDenserCells) {
  OccupancyGrid grid(kBox, 32, 0.01f);
  std::mt19937 rng(5);
  grid.update([](std::span<const glm::vec3> points, std::span<float> sigmas) {
    for (std::size_t i = 0; i < points.size(); ++i)
      sigmas[i] = glm::length(points[i] - kSphereCentre) < kSphereRadius ? 0.005f : 0.001f;
  }, rng, {.decay = 0.95f, .jitter = false, .cells = 0});
  std::size_t inside = 0;
  for (std::size_t c = 0; c < grid.cell_count(); ++c) {
    const bool centre_inside = glm::length(grid.cell_center(c) - kSphereCentre) < kSphereRadius;
    EXPECT_EQ(grid.cell_occupied(c), centre_inside) << c;
    inside += centre_inside;
  }
  EXPECT_GT(inside, 1000u);
}

TEST(NerfOccupancy, ValuesDecayUntilTheCellEmpties) {
  OccupancyGrid grid(kBox, 4, 0.5f);
  std::mt19937 rng(4);
  auto constant = [](float sigma) {
    return [sigma](std::span<const glm::vec3>, std::span<float> sigmas) {
      for (float& s : sigmas) s = sigma;
    };
  };
  grid.update(constant(1.0f), rng);
  EXPECT_EQ(grid.occupied_count(), grid.cell_count());
  // With σ = 0 from now on, value = 0.95ᵏ: 0.95¹³ = 0.513 > 0.5, 0.95¹⁴ = 0.488 < 0.5.
  for (int k = 1; k <= 13; ++k) grid.update(constant(0.0f), rng);
  EXPECT_EQ(grid.occupied_count(), grid.cell_count());
  EXPECT_NEAR(grid.cell_value(0), std::pow(0.95f, 13.0f), 1e-6f);
  grid.update(constant(0.0f), rng);
  EXPECT_EQ(grid.occupied_count(), 0u);
  // One high sample reopens a cell at once (max, not average).
  grid.update(constant(0.6f), rng);
  EXPECT_EQ(grid.occupied_count(), grid.cell_count());
}

TEST(NerfOccupancy, UpdatesAreDeterministicForAnyThreadCount) {
  std::vector<float> values[3];
  std::vector<bool> occupied[3];
  const int threads[3] = {1, 2, 2};
  for (int run = 0; run < 3; ++run) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads[run]);
    OccupancyGrid grid(kBox, 20);
    std::size_t calls = 0;
    std::mt19937 rng(5);
    grid.update(SphereDensity{&calls}, rng);  // all cells, jittered
    grid.update(SphereDensity{&calls}, rng, {.decay = 0.9f, .jitter = true, .cells = 3000});
    EXPECT_EQ(calls, grid.cell_count() + 3000);
    for (std::size_t c = 0; c < grid.cell_count(); ++c) {
      values[run].push_back(grid.cell_value(c));
      occupied[run].push_back(grid.cell_occupied(c));
    }
  }
  EXPECT_EQ(values[0], values[1]);
  EXPECT_EQ(values[1], values[2]);
  EXPECT_EQ(occupied[0], occupied[1]);
}

TEST(NerfOccupancy, RejectsBadArguments) {
  EXPECT_THROW(OccupancyGrid(kBox, 0), ArgumentError);
  EXPECT_THROW(OccupancyGrid(AxisAlignedBox{glm::vec3(0.0f), glm::vec3(0.0f, 1.0f, 1.0f)}, 8),
               ArgumentError);
  const OccupancyGrid grid(kBox, 8);
  std::vector<float> t(3), delta(2);
  EXPECT_THROW(drop_empty_samples(grid, SceneSpace{kBox}, Ray{glm::vec3(0.0f), glm::vec3(1, 0, 0)}, t, delta),
               ArgumentError);
}

}  // namespace
}  // namespace splat
