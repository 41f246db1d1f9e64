// The occupancy grid's density threshold follows the scene's scale: a cell is empty when one
// coarse step through it is less than occupancy_optical_thickness opaque.
#include <gtest/gtest.h>

#include <cmath>

#include "splat/nerf/nerf_file.hpp"
#include "splat/nerf/nerf_model.hpp"

namespace splat {
namespace {

TEST(OccupancyThreshold, IsTheOpticalThicknessOverTheCoarseStep) {
  NerfSettings s;  // ±1.5 box, 64 coarse samples
  const float step = std::sqrt(27.0f) / 64.0f;
  EXPECT_NEAR(s.coarse_step(), step, 1e-6f);
  EXPECT_NEAR(s.occupancy_density_threshold(), 0.01f / step, 1e-5f);
  EXPECT_NEAR(NerfModel(s, 0).grid.threshold(), 0.01f / step, 1e-5f);
  // Ten times the scene: a tenth of the density threshold, the same opacity per step.
  s.box = {glm::vec3(-15.0f), glm::vec3(15.0f)};
  EXPECT_NEAR(s.occupancy_density_threshold(), 0.001f / step, 1e-6f);
  // Unbounded, half the coarse samples lie in the box: steps twice as long.
  s.unbounded = true;
  EXPECT_NEAR(s.coarse_step(), 20.0f * step, 1e-4f);
}

TEST(OccupancyThreshold, AnOldDensityThresholdReadsAsTheSameDensity) {
  const NerfSettings defaults;
  nlohmann::json old = nerf_settings_json(defaults);
  old.erase("occupancy_optical_thickness");
  old["occupancy_threshold"] = 0.01f;  // a density, as files before the optical thickness held
  const NerfSettings read = nerf_settings_from_json(old);
  EXPECT_NEAR(read.occupancy_density_threshold(), 0.01f, 1e-7f);
  EXPECT_EQ(nerf_settings_from_json(nerf_settings_json(defaults)).occupancy_optical_thickness,
            defaults.occupancy_optical_thickness);
}

}  // namespace
}  // namespace splat
