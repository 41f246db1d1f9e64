#include "splat/raster/project.hpp"

#include <algorithm>
#include <cmath>
#include <tbb/parallel_for.h>

#include "splat/core/simd.hpp"
#include "splat/core/spherical_harmonics.hpp"
#include "splat/raster/pixel_projection.hpp"
#include "splat/raster/projection_math.hpp"

namespace splat {

namespace {

// Tiles that the box |dx| <= ex, |dy| <= ey around (x, y) touches.
TileRect extent_tile_rect(float x, float y, float ex, float ey, const TileGrid& grid) {
  auto tile_lo = [](float v, int limit) {
    return int(std::clamp(std::floor(v / kTileSize), 0.0f, float(limit)));
  };
  auto tile_hi = [](float v, int limit) {
    return int(std::clamp(std::floor(v / kTileSize) + 1.0f, 0.0f, float(limit)));
  };
  return {tile_lo(x - ex, grid.tiles_x), tile_lo(y - ey, grid.tiles_y),
          tile_hi(x + ex, grid.tiles_x), tile_hi(y + ey, grid.tiles_y)};
}

TileRect intersect(const TileRect& a, const TileRect& b) {
  TileRect r{std::max(a.x0, b.x0), std::max(a.y0, b.y0), std::min(a.x1, b.x1),
             std::min(a.y1, b.y1)};
  if (r.x1 <= r.x0 || r.y1 <= r.y0) r = {0, 0, 0, 0};
  return r;
}

float sigmoid(float x) { return 1.0f / (1.0f + std::exp(-x)); }

using simd::f32v;
using simd::kLanes;

// max(SH(dir) + 0.5, 0) per channel for Gaussians first .. first + lanes − 1, one per lane
// (the lanes past `lanes` repeat the last Gaussian).
void sh_colors(const GaussianModel& model, std::size_t first, int lanes, int degree, f32v dir_x,
               f32v dir_y, f32v dir_z, f32v rgb[3]) {
  f32v basis[16];
  sh_basis_xyz(degree, dir_x, dir_y, dir_z, basis);
  const std::size_t stride = std::size_t(model.sh_coefficients()) * 3;
  const float* coeffs[kLanes];
  for (int l = 0; l < kLanes; ++l) coeffs[l] = &model.sh[(first + std::size_t(std::min(l, lanes - 1))) * stride];
  f32v sum[3] = {};
  const int count = (degree + 1) * (degree + 1);
  for (int k = 0; k < count; ++k)
    for (int c = 0; c < 3; ++c) {
      f32v coeff;
      for (int l = 0; l < kLanes; ++l) coeff[l] = coeffs[l][3 * k + c];
      sum[c] += basis[k] * coeff;
    }
  for (int c = 0; c < 3; ++c) {
    const f32v raw = sum[c] + 0.5f;
    rgb[c] = simd::select(raw < 0.0f, f32v{}, raw);  // as std::max(raw, 0.0f) per lane
  }
}

}  // namespace

TileRect reference_tile_rect(float x, float y, int r, const TileGrid& grid) {
  // Truncation toward zero, then clamping, exactly as the reference does.
  auto bound = [](float v, int limit) { return std::min(limit, std::max(0, int(v / kTileSize))); };
  return {bound(x - float(r), grid.tiles_x), bound(y - float(r), grid.tiles_y),
          bound(x + float(r + kTileSize - 1), grid.tiles_x),
          bound(y + float(r + kTileSize - 1), grid.tiles_y)};
}

TileGrid TileGrid::for_image(int width, int height) {
  return {(width + kTileSize - 1) / kTileSize, (height + kTileSize - 1) / kTileSize};
}

void project_gaussians(const GaussianModel& model, const Camera& camera, int sh_degree,
                       ProjectedGaussians& out) {
  const std::size_t n = model.size();
  out.splats.resize(n);
  out.radius.resize(n);
  out.tiles.resize(n);
  const TileGrid grid = TileGrid::for_image(camera.width, camera.height);
  const int degree = std::clamp(sh_degree, 0, model.sh_degree);
  const glm::vec3 camera_center = camera.center_in_world();
  const float tan_fov_x = camera.tan_half_fov_x(), tan_fov_y = camera.tan_half_fov_y();
  const PixelProjection pixel_of(camera);

  // Everything but the colour, one Gaussian at a time; returns whether the Gaussian is drawn
  // (then its unit view direction is in `dir`).
  auto project_one = [&](std::size_t i, glm::vec3& dir) -> bool {
    out.radius[i] = 0;
    out.tiles[i] = {0, 0, 0, 0};
    const glm::vec3 mean(model.means[3 * i], model.means[3 * i + 1], model.means[3 * i + 2]);
    const glm::vec3 mean_camera = camera.camera_from_world(mean);
    if (!(mean_camera.z > kNearPlane)) return false;  // also drops a NaN position

    const glm::vec3 scale(std::exp(model.log_scales[3 * i]), std::exp(model.log_scales[3 * i + 1]),
                          std::exp(model.log_scales[3 * i + 2]));
    const glm::vec4 quat(model.quats[4 * i], model.quats[4 * i + 1], model.quats[4 * i + 2],
                         model.quats[4 * i + 3]);
    const Mat3<float> cov3d = covariance_3d(scale, quat_to_rotmat(quat));
    const Sym2<float> cov2d = covariance_2d(mean_camera, cov3d, camera.camera_from_world_rotation,
                                            camera.fx, camera.fy, tan_fov_x, tan_fov_y);
    Vec3<float> conic;
    if (!invert_covariance_2d(cov2d, conic)) return false;
    const Vec2<float> center = pixel_of(mean);
    // Non-finite or absurd footprints (NaN parameters, scales overflowing exp) would make
    // the integer tile arithmetic below undefined; they cannot be drawn, so they are culled.
    constexpr float kMaxFootprint = 1e7f;
    if (!(std::abs(center.x) < kMaxFootprint && std::abs(center.y) < kMaxFootprint &&
          cov2d.xx < kMaxFootprint * kMaxFootprint && cov2d.yy < kMaxFootprint * kMaxFootprint &&
          std::isfinite(conic.x) && std::isfinite(conic.y) && std::isfinite(conic.z)))
      return false;
    const int radius = screen_radius(cov2d);
    TileRect rect = reference_tile_rect(center.x, center.y, radius, grid);
    if (rect.count() == 0) return false;
    out.radius[i] = radius;

    Splat2D& s = out.splats[i];
    s.mean_x = center.x;
    s.mean_y = center.y;
    s.conic_a = conic.x;
    s.conic_b = conic.y;
    s.conic_c = conic.z;
    s.opacity = sigmoid(model.opacity_logits[i]);
    s.depth = mean_camera.z;
    dir = glm::normalize(mean - camera_center);

    // α = o·exp(−q/2) ≥ kMinAlpha exactly where q ≤ 2 ln(o / kMinAlpha); the box around
    // that ellipse is ±sqrt(q_max · Σ'ᵢᵢ). Outside it nothing is blended, so only tiles
    // (and, in blending, pixels) inside it need visiting. A small margin absorbs rounding.
    const float q_max = 2.0f * std::log(s.opacity / kMinAlpha);
    s.q_max = q_max;
    if (!(q_max > 0.0f)) {
      s.extent_x = s.extent_y = 0.0f;
      return false;  // too transparent to ever reach kMinAlpha
    }
    constexpr float kRelativeMargin = 1e-3f, kAbsoluteMargin = 1e-2f;
    s.extent_x = std::sqrt(q_max * cov2d.xx) * (1 + kRelativeMargin) + kAbsoluteMargin;
    s.extent_y = std::sqrt(q_max * cov2d.yy) * (1 + kRelativeMargin) + kAbsoluteMargin;
    rect = intersect(rect, extent_tile_rect(center.x, center.y, s.extent_x, s.extent_y, grid));
    out.tiles[i] = rect;
    return true;
  };

  // The colours kLanes Gaussians at a time: one by one, the SH sums of degree 3 were about
  // 40 % of the projection (219k-Gaussian benchmark model at 800²: 11.1 ms, 6.8 at degree 0).
  // Each lane sums in sh_evaluate's order.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const auto& range) {
    for (std::size_t first = range.begin(); first < range.end(); first += kLanes) {
      const int lanes = int(std::min<std::size_t>(kLanes, range.end() - first));
      f32v dir_x{}, dir_y{}, dir_z{};
      std::uint32_t drawn = 0;
      for (int l = 0; l < lanes; ++l) {
        glm::vec3 dir(0.0f, 0.0f, 1.0f);
        if (project_one(first + l, dir)) drawn |= 1u << l;
        dir_x[l] = dir.x;
        dir_y[l] = dir.y;
        dir_z[l] = dir.z;
      }
      if (drawn == 0) continue;
      f32v rgb[3];
      sh_colors(model, first, lanes, degree, dir_x, dir_y, dir_z, rgb);
      for (; drawn != 0; drawn &= drawn - 1) {
        const int l = __builtin_ctz(drawn);
        for (int c = 0; c < 3; ++c) out.splats[first + l].color[c] = rgb[c][l];
      }
    }
  });
}

}  // namespace splat
