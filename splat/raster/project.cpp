#include "splat/raster/project.hpp"

#include <algorithm>
#include <cmath>
#include <tbb/parallel_for.h>

#include "splat/core/activations.hpp"
#include "splat/core/simd.hpp"
#include "splat/core/spherical_harmonics.hpp"
#include "splat/raster/lane_projection.hpp"
#include "splat/raster/pixel_projection.hpp"
#include "splat/raster/projection_math.hpp"

namespace splat {

namespace {

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
  const int count = (degree + 1) * (degree + 1);
  f32v coeff[kMaxShFloats];
  simd::load_columns(coeffs, 3 * count, coeff);
  f32v sum[3] = {};
  for (int k = 0; k < count; ++k)
    for (int c = 0; c < 3; ++c) sum[c] += basis[k] * coeff[3 * k + c];
  for (int c = 0; c < 3; ++c) {
    const f32v raw = sum[c] + 0.5f;
    rgb[c] = simd::select(raw < 0.0f, f32v{}, raw);  // as std::max(raw, 0.0f) per lane
  }
}

// ---- kLanes Gaussians at a time -------------------------------------------------------
// The projection is projection_math.hpp's scalar functions (which the backward pass
// differentiates) written out for kLanes Gaussians, one per lane, term for term in the same
// order (lane_projection.hpp, shared with the backward). One Gaussian at a time it cost ~68 ns
// per Gaussian and core; this is about half. Pixel position, depth, opacity and culling come
// out bit for bit as the scalar code's; the covariance sums may round a few ulp apart, where
// the compiler fuses products into FMAs differently (tests/raster/project_lanes_test.cpp
// bounds both). exp and log stay libm's, one lane at a time.

using simd::i32v;
using namespace lanes;

// The tiles a Gaussian of each lane touches, as integer vectors.
struct LaneTileRect {
  i32v x0, y0, x1, y1;
};

// reference_tile_rect per lane.
LaneTileRect reference_tile_rects(f32v x, f32v y, i32v r, const TileGrid& grid) {
  auto bound = [](f32v v, int limit) {
    return min_of(i32v{} + limit, max_of(i32v{}, __builtin_convertvector(v / float(kTileSize), i32v)));
  };
  const f32v rf = __builtin_convertvector(r, f32v);
  const f32v reach = __builtin_convertvector(r + (kTileSize - 1), f32v);
  return {bound(x - rf, grid.tiles_x), bound(y - rf, grid.tiles_y), bound(x + reach, grid.tiles_x),
          bound(y + reach, grid.tiles_y)};
}

// The tiles that the box |dx| <= ex, |dy| <= ey around (x, y) touches, per lane, intersected
// with `rect` (all zero where empty).
LaneTileRect clip_to_extent(const LaneTileRect& rect, f32v x, f32v y, f32v ex, f32v ey,
                            const TileGrid& grid) {
  auto clamp_to_int = [](f32v v, int limit) {  // std::clamp(v, 0, limit)
    const f32v hi = simd::broadcast(float(limit));
    return __builtin_convertvector(v < 0.0f ? f32v{} : (hi < v ? hi : v), i32v);
  };
  auto tile_lo = [&](f32v v, int limit) { return clamp_to_int(simd::floor(v / float(kTileSize)), limit); };
  auto tile_hi = [&](f32v v, int limit) {
    return clamp_to_int(simd::floor(v / float(kTileSize)) + 1.0f, limit);
  };
  LaneTileRect r{max_of(rect.x0, tile_lo(x - ex, grid.tiles_x)), max_of(rect.y0, tile_lo(y - ey, grid.tiles_y)),
                 min_of(rect.x1, tile_hi(x + ex, grid.tiles_x)), min_of(rect.y1, tile_hi(y + ey, grid.tiles_y))};
  const i32v empty = (r.x1 <= r.x0) | (r.y1 <= r.y0);
  r.x0 = empty ? i32v{} : r.x0;
  r.y0 = empty ? i32v{} : r.y0;
  r.x1 = empty ? i32v{} : r.x1;
  r.y1 = empty ? i32v{} : r.y1;
  return r;
}

// What project_gaussians needs of the camera, computed once per frame.
struct LaneCamera {
  LaneView view;
  glm::vec3 center;
  PixelProjection pixel_of;
  TileGrid grid;

  explicit LaneCamera(const Camera& camera)
      : view(camera),
        center(camera.center_in_world()),
        pixel_of(camera),
        grid(TileGrid::for_image(camera.width, camera.height)) {}
};

// Projects Gaussians first .. first + lanes − 1 into `out`, as the scalar functions would
// one by one. Returns the lanes drawn (bit l for Gaussian first + l); their unit view
// directions are in dir.
std::uint32_t project_lanes(const GaussianModel& model, std::size_t first, int lanes,
                            const LaneCamera& cam, ProjectedGaussians& out, f32v dir[3]) {
  const LaneGaussians g(model, first, lanes);
  const LaneShape shape(g, cam.view);
  const f32v z = shape.mean_camera[2];
  i32v projected = z > kNearPlane;  // also drops a NaN position
  const f32v xx = shape.xx, xy = shape.xy, yy = shape.yy;
  const f32v zero{};

  // invert_covariance_2d.
  const f32v det = xx * yy - xy * xy;
  projected &= det != 0.0f;
  const f32v inv_det = 1.0f / det;
  const f32v conic_a = yy * inv_det, conic_b = -xy * inv_det, conic_c = xx * inv_det;
  f32v center_x, center_y;
  cam.pixel_of(g.mean[0], g.mean[1], g.mean[2], center_x, center_y);
  // Non-finite or absurd footprints (NaN parameters, scales overflowing exp) would make
  // the integer tile arithmetic below undefined; they cannot be drawn, so they are culled.
  constexpr float kMaxFootprint = 1e7f, kMaxFinite = 3.40282347e38f;
  projected &= (simd::abs(center_x) < kMaxFootprint) & (simd::abs(center_y) < kMaxFootprint) &
               (xx < kMaxFootprint * kMaxFootprint) & (yy < kMaxFootprint * kMaxFootprint) &
               (simd::abs(conic_a) <= kMaxFinite) & (simd::abs(conic_b) <= kMaxFinite) &
               (simd::abs(conic_c) <= kMaxFinite);

  // screen_radius.
  const f32v mid = 0.5f * (xx + yy);
  const f32v lambda_max = mid + simd::sqrt(max_of(simd::broadcast(kMinEigenGap), mid * mid - det));
  const i32v radius = __builtin_convertvector(simd::ceil(kRadiusSigmas * simd::sqrt(lambda_max)), i32v);
  const LaneTileRect rect = reference_tile_rects(center_x, center_y, radius, cam.grid);
  projected &= (rect.x1 != rect.x0) & (rect.y1 != rect.y0);

  const f32v opacity = simd::sigmoid(g.opacity_logit);
  const f32v to_x = g.mean[0] - cam.center.x, to_y = g.mean[1] - cam.center.y, to_z = g.mean[2] - cam.center.z;
  const f32v inv_length = 1.0f / simd::sqrt(to_x * to_x + to_y * to_y + to_z * to_z);  // glm::normalize
  dir[0] = to_x * inv_length;
  dir[1] = to_y * inv_length;
  dir[2] = to_z * inv_length;

  // α = o·exp(−q/2) ≥ kMinAlpha exactly where q ≤ 2 ln(o / kMinAlpha); the box around
  // that ellipse is ±sqrt(q_max · Σ'ᵢᵢ). Outside it nothing is blended, so only tiles
  // (and, in blending, pixels) inside it need visiting. A small margin absorbs rounding.
  const f32v q_max = 2.0f * simd::per_lane(opacity / kMinAlpha, log_of);
  const i32v reaches = q_max > 0.0f;  // else too transparent to ever reach kMinAlpha
  constexpr float kRelativeMargin = 1e-3f, kAbsoluteMargin = 1e-2f;
  f32v extent_x = simd::sqrt(q_max * xx) * (1 + kRelativeMargin) + kAbsoluteMargin;
  f32v extent_y = simd::sqrt(q_max * yy) * (1 + kRelativeMargin) + kAbsoluteMargin;
  extent_x = reaches ? extent_x : zero;
  extent_y = reaches ? extent_y : zero;
  const LaneTileRect tiles = clip_to_extent(rect, center_x, center_y, extent_x, extent_y, cam.grid);

  const std::uint32_t projected_bits = simd::bits(projected) & ((1u << lanes) - 1);
  const std::uint32_t drawn = projected_bits & simd::bits(reaches);
  for (int l = 0; l < lanes; ++l) {
    const std::size_t i = first + std::size_t(l);
    const bool is_drawn = (drawn >> l) & 1;
    out.radius[i] = (projected_bits >> l) & 1 ? radius[l] : 0;
    out.tiles[i] = is_drawn ? TileRect{tiles.x0[l], tiles.y0[l], tiles.x1[l], tiles.y1[l]} : TileRect{0, 0, 0, 0};
    if (!((projected_bits >> l) & 1)) continue;
    Splat2D& s = out.splats[i];
    s.mean_x = center_x[l];
    s.mean_y = center_y[l];
    s.conic_a = conic_a[l];
    s.conic_b = conic_b[l];
    s.conic_c = conic_c[l];
    s.opacity = opacity[l];
    s.depth = z[l];
    s.q_max = q_max[l];
    s.extent_x = extent_x[l];
    s.extent_y = extent_y[l];
  }
  return drawn;
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
  const int degree = std::clamp(sh_degree, 0, model.sh_degree);
  const LaneCamera lane_camera(camera);
  // The SH colours too kLanes Gaussians at a time: one by one, the SH sums of degree 3 were
  // about 40 % of the projection (219k-Gaussian benchmark model at 800²: 11.1 ms, 6.8 at
  // degree 0). Each lane sums in sh_evaluate's order.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const auto& range) {
    for (std::size_t first = range.begin(); first < range.end(); first += kLanes) {
      const int lanes = int(std::min<std::size_t>(kLanes, range.end() - first));
      f32v dir[3];
      std::uint32_t drawn = project_lanes(model, first, lanes, lane_camera, out, dir);
      if (drawn == 0) continue;
      f32v rgb[3];
      sh_colors(model, first, lanes, degree, dir[0], dir[1], dir[2], rgb);
      for (; drawn != 0; drawn &= drawn - 1) {
        const int l = __builtin_ctz(drawn);
        for (int c = 0; c < 3; ++c) out.splats[first + l].color[c] = rgb[c][l];
      }
    }
  });
}

}  // namespace splat
