// project_gaussians computes kLanes Gaussians at a time; every lane must give what
// projection_math.hpp's scalar functions give one Gaussian at a time (the backward pass and
// the double-precision tests use those). The reference below composes them as the
// projection did before it was vectorised. The pixel position, depth and opacity are exact
// to the bit (explicit fma and libm's exp); the covariance sums round a few ulp differently,
// because the compiler fuses the scalar and the vector products into FMAs differently.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <utility>

#include "splat/core/spherical_harmonics.hpp"
#include "splat/raster/pixel_projection.hpp"
#include "splat/raster/project.hpp"
#include "splat/raster/projection_math.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

// One Gaussian with the scalar functions: returns whether it is drawn; fills `radius`,
// `tiles` and (from the reference's screen radius on) the splat, as project_gaussians does.
bool project_one(const GaussianModel& model, const Camera& camera, int degree, std::size_t i,
                 int& radius, TileRect& tiles, Splat2D& s) {
  radius = 0;
  tiles = {0, 0, 0, 0};
  const TileGrid grid = TileGrid::for_image(camera.width, camera.height);
  const glm::vec3 mean(model.means[3 * i], model.means[3 * i + 1], model.means[3 * i + 2]);
  const glm::vec3 mean_camera = camera.camera_from_world(mean);
  if (!(mean_camera.z > kNearPlane)) return false;
  const glm::vec3 scale(std::exp(model.log_scales[3 * i]), std::exp(model.log_scales[3 * i + 1]),
                        std::exp(model.log_scales[3 * i + 2]));
  const glm::vec4 quat(model.quats[4 * i], model.quats[4 * i + 1], model.quats[4 * i + 2],
                       model.quats[4 * i + 3]);
  const Sym2<float> cov2d =
      covariance_2d(mean_camera, covariance_3d(scale, quat_to_rotmat(quat)), camera.camera_from_world_rotation,
                    camera.fx, camera.fy, camera.tan_half_fov_x(), camera.tan_half_fov_y());
  Vec3<float> conic;
  if (!invert_covariance_2d(cov2d, conic)) return false;
  const Vec2<float> center = PixelProjection(camera)(mean);
  if (!(std::abs(center.x) < 1e7f && std::abs(center.y) < 1e7f && cov2d.xx < 1e14f && cov2d.yy < 1e14f &&
        std::isfinite(conic.x) && std::isfinite(conic.y) && std::isfinite(conic.z)))
    return false;
  const int r = screen_radius(cov2d);
  const TileRect rect = reference_tile_rect(center.x, center.y, r, grid);
  if (rect.count() == 0) return false;
  radius = r;
  s.mean_x = center.x;
  s.mean_y = center.y;
  s.conic_a = conic.x;
  s.conic_b = conic.y;
  s.conic_c = conic.z;
  s.opacity = 1.0f / (1.0f + std::exp(-model.opacity_logits[i]));
  s.depth = mean_camera.z;
  s.q_max = 2.0f * std::log(s.opacity / kMinAlpha);
  if (!(s.q_max > 0.0f)) {
    s.extent_x = s.extent_y = 0.0f;
    return false;
  }
  s.extent_x = std::sqrt(s.q_max * cov2d.xx) * (1 + 1e-3f) + 1e-2f;
  s.extent_y = std::sqrt(s.q_max * cov2d.yy) * (1 + 1e-3f) + 1e-2f;
  auto tile_lo = [](float v, int limit) {
    return int(std::clamp(std::floor(v / kTileSize), 0.0f, float(limit)));
  };
  auto tile_hi = [](float v, int limit) {
    return int(std::clamp(std::floor(v / kTileSize) + 1.0f, 0.0f, float(limit)));
  };
  tiles = {std::max(rect.x0, tile_lo(center.x - s.extent_x, grid.tiles_x)),
           std::max(rect.y0, tile_lo(center.y - s.extent_y, grid.tiles_y)),
           std::min(rect.x1, tile_hi(center.x + s.extent_x, grid.tiles_x)),
           std::min(rect.y1, tile_hi(center.y + s.extent_y, grid.tiles_y))};
  if (tiles.x1 <= tiles.x0 || tiles.y1 <= tiles.y0) tiles = {0, 0, 0, 0};
  const glm::vec3 dir = glm::normalize(mean - camera.center_in_world());
  const std::size_t stride = std::size_t(model.sh_coefficients()) * 3;
  const glm::vec3 rgb = sh_evaluate(degree, &model.sh[i * stride], dir);
  for (int c = 0; c < 3; ++c) s.color[c] = std::max(rgb[c] + 0.5f, 0.0f);
  return true;
}

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof(float)) == 0; }

// |a − b| relative to the larger magnitude (0 when both are 0).
double relative_difference(float a, float b) {
  const double scale = std::max(std::abs(double(a)), std::abs(double(b)));
  return scale == 0 ? 0 : std::abs(double(a) - double(b)) / scale;
}

// Bounds of the differences. The conic is Σ'⁻¹: its rounding error grows with the condition
// of the determinant xx·yy − xy², κ = (xx·yy + xy²) / |det|, so its difference is measured
// relative to κ times its largest entry (a nearly singular Σ' loses that many digits in any
// float evaluation, the official rasterizer's included).
constexpr double kMaxConicDifference = 1e-5, kMaxExtentDifference = 1e-5, kMaxColorDifference = 1e-6;

// Every Gaussian of `model` seen by `camera`: the vectorised projection against project_one.
// Returns how many were drawn.
int expect_lanes_match_scalar(const GaussianModel& model, const Camera& camera, int degree) {
  ProjectedGaussians lanes;
  project_gaussians(model, camera, degree, lanes);
  int drawn = 0, mismatches = 0;
  double worst_conic = 0, worst_extent = 0, worst_color = 0;
  for (std::size_t i = 0; i < model.size() && mismatches < 5; ++i) {
    int radius;
    TileRect tiles;
    Splat2D s{};
    const bool is_drawn = project_one(model, camera, degree, i, radius, tiles, s);
    drawn += is_drawn;
    const Splat2D& v = lanes.splats[i];
    bool same = radius == lanes.radius[i] && tiles.x0 == lanes.tiles[i].x0 && tiles.y0 == lanes.tiles[i].y0 &&
                tiles.x1 == lanes.tiles[i].x1 && tiles.y1 == lanes.tiles[i].y1;
    if (radius > 0) {  // the splat record is only defined for Gaussians with a screen radius
      same = same && same_bits(s.mean_x, v.mean_x) && same_bits(s.mean_y, v.mean_y) &&
             same_bits(s.depth, v.depth) && same_bits(s.opacity, v.opacity) && same_bits(s.q_max, v.q_max);
      // Σ' from the scalar conic (its inverse), for κ.
      const double a = s.conic_a, b = s.conic_b, c = s.conic_c;
      const double condition = (a * c + b * b) / std::abs(a * c - b * b);
      const double conic_scale = condition * std::max({std::abs(a), std::abs(b), std::abs(c)});
      for (auto [a, b] : {std::pair{s.conic_a, v.conic_a}, {s.conic_b, v.conic_b}, {s.conic_c, v.conic_c}})
        worst_conic = std::max(worst_conic, std::abs(double(a) - double(b)) / conic_scale);
      for (auto [a, b] : {std::pair{s.extent_x, v.extent_x}, {s.extent_y, v.extent_y}})
        worst_extent = std::max(worst_extent, relative_difference(a, b));
    }
    if (is_drawn)
      for (int c = 0; c < 3; ++c) worst_color = std::max(worst_color, double(std::abs(s.color[c] - v.color[c])));
    if (!same) {
      ++mismatches;
      ADD_FAILURE() << "Gaussian " << i << ": radius " << radius << " vs " << lanes.radius[i] << ", mean "
                    << s.mean_x << "," << s.mean_y << " vs " << v.mean_x << "," << v.mean_y << ", tiles "
                    << tiles.x0 << ".." << tiles.x1 << " vs " << lanes.tiles[i].x0 << ".." << lanes.tiles[i].x1;
    }
  }
  EXPECT_LE(worst_conic, kMaxConicDifference);
  EXPECT_LE(worst_extent, kMaxExtentDifference);
  EXPECT_LE(worst_color, kMaxColorDifference);
  std::printf("%zu Gaussians, %d drawn: largest difference: conic %.2g (of κ · its largest entry), extent %.2g (relative), colour %.2g\n",
              model.size(), drawn, worst_conic, worst_extent, worst_color);
  return drawn;
}

TEST(ProjectLanes, EveryLaneRoundsAsTheScalarFunctions) {
  // Random Gaussians, some behind the camera, some very flat, some nearly transparent, and
  // a count that is not a multiple of the lanes or the parallel grain.
  GaussianModel model = test::random_model(5003, 3, 11, 2.5f, 0.001f, 0.8f);
  for (std::size_t i = 0; i < model.size(); i += 5) model.opacity_logits[i] = -6.0f + 0.001f * float(i);
  for (std::size_t i = 0; i < model.size(); i += 7) model.log_scales[3 * i + 1] = std::log(1e-5f);
  const Camera camera = test::looking_at_origin(173, 111, 3.0f, 0.9f);
  for (int degree : {0, 1, 3}) EXPECT_GT(expect_lanes_match_scalar(model, camera, degree), 1000);
}

TEST(ProjectLanes, NonFiniteAndExtremeParametersMatchTheScalarCulling) {
  GaussianModel model = test::random_model(64, 1, 3, 1.0f);
  model.means[3 * 1] = std::nanf("");
  model.log_scales[3 * 2] = 200.0f;
  for (int k = 0; k < 4; ++k) model.quats[4 * 3 + k] = 0.0f;
  model.opacity_logits[4] = std::nanf("");
  model.means[3 * 5 + 2] = 1e30f;
  model.log_scales[3 * 6] = model.log_scales[3 * 6 + 1] = 15.0f;  // huge footprint
  model.sh[0] = std::numeric_limits<float>::infinity();
  expect_lanes_match_scalar(model, test::looking_at_origin(64, 48), 1);
}

TEST(ProjectLanes, ConformanceModelMatchesTheScalarFunctions) {
  const test::ConformanceScene scene = test::load_conformance(800);
  ASSERT_FALSE(scene.frames.empty());
  EXPECT_GT(expect_lanes_match_scalar(scene.model, scene.frames[0].camera, 3), 10000);
}

}  // namespace
}  // namespace splat
