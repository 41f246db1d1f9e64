// The requirement for "one compositor": a NeRF ray and a splat pixel fed the same
// (α, colour, depth) sequence give identical colour, alpha, depth and gradients.
//
// (a) The NeRF path: composite_ray / composite_ray_vjp (ray_composite.hpp), the α-level
//     functions volume_render calls after α = 1 − exp(−σδ). They take α directly, so the
//     sequence enters exactly, without a σ round trip.
// (b) The rasterizer path: the production tile blend (blend_tiles / blend_tiles_backward,
//     the SIMD code the Rasterizer runs), given one tile whose list holds one Splat2D per
//     sample, in sequence order, centred on the test pixel with a zero conic. There the
//     Gaussian factor is exp(0) = 1 exactly, so the rasterizer's α = min(0.99, o·G) = o is
//     the sequence's α (all in [1/255, 0.99], so none is skipped or clamped), and its
//     ∂L/∂o = G·∂L/∂α = ∂L/∂α.
// Both run the same composite_step / composite_step_vjp (see expect_identical for why the
// comparison is to a few rounding errors rather than bitwise).
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <random>
#include <vector>

#include "splat/core/random.hpp"
#include "splat/nerf/ray_composite.hpp"
#include "splat/raster/blend.hpp"
#include "splat/raster/blend_backward.hpp"
#include "splat/raster/raster_constants.hpp"

namespace splat {
namespace {

constexpr float kBackground[3] = {0.25f, 0.5f, 1.0f};
constexpr int kPixelX = 5, kPixelY = 9;  // inside the single 16×16 tile

struct Sequence {
  std::vector<float> alpha, rgb, depth;  // [n], [n, 3], [n] front to back
  std::size_t size() const { return alpha.size(); }
};

// n samples with α uniform in [1/255, 0.99] plus the two end points themselves, colours in
// [0, 1], depths increasing. `opaque` makes the later α large so the T floor is reached.
Sequence make_sequence(int n, unsigned seed, bool opaque) {
  std::mt19937 rng(seed);
  Sequence s;
  float z = 1.0f;
  for (int i = 0; i < n; ++i) {
    float a = kMinAlpha + (kMaxAlpha - kMinAlpha) * uniform01(rng);
    if (i == 1) a = kMinAlpha;
    if (i == 2) a = kMaxAlpha;
    if (opaque && i >= n / 2) a = 0.9f + 0.09f * uniform01(rng);
    s.alpha.push_back(a);
    for (int c = 0; c < 3; ++c) s.rgb.push_back(uniform01(rng));
    z += 0.1f + uniform01(rng);
    s.depth.push_back(z);
  }
  return s;
}

struct Outcome {
  float color[3], alpha, depth, final_transmittance;
  std::uint32_t blended;
  std::vector<float> v_alpha, v_rgb;  // [n], [n, 3]
  std::vector<float> weights;         // [n] Tᵢαᵢ, NeRF side only
};

Outcome through_nerf(const Sequence& s, const float v_color[3]) {
  const std::size_t n = s.size();
  std::vector<float> weights(n);
  const RayComposite<float> r =
      composite_ray(n, s.alpha.data(), s.rgb.data(), s.depth.data(), kBackground, weights.data());
  Outcome o{{r.color[0], r.color[1], r.color[2]}, r.alpha, r.depth, r.final_transmittance,
            r.blended_count, std::vector<float>(n), std::vector<float>(3 * n), weights};
  composite_ray_vjp(n, s.alpha.data(), s.rgb.data(), r, kBackground, v_color, o.v_alpha.data(),
                    o.v_rgb.data());
  return o;
}

Outcome through_rasterizer(const Sequence& s, const float v_color[3]) {
  const std::size_t n = s.size();
  ProjectedGaussians projected;
  for (std::size_t i = 0; i < n; ++i) {
    Splat2D splat{};
    splat.mean_x = float(kPixelX);
    splat.mean_y = float(kPixelY);
    splat.conic_a = splat.conic_b = splat.conic_c = 0.0f;  // G = exp(0) = 1 everywhere
    splat.opacity = s.alpha[i];
    for (int c = 0; c < 3; ++c) splat.color[c] = s.rgb[3 * i + c];
    splat.depth = s.depth[i];
    splat.extent_x = splat.extent_y = 0.5f;  // the box holds our pixel only
    projected.splats.push_back(splat);
    projected.radius.push_back(1);
    projected.tiles.push_back(TileRect{0, 0, 1, 1});
  }
  const TileGrid grid = TileGrid::for_image(kTileSize, kTileSize);
  TileBins bins;
  for (std::size_t i = 0; i < n; ++i) {
    bins.gaussian_ids.push_back(std::uint32_t(i));  // depth order
    bins.entry_overlap.push_back(std::uint32_t(i));  // one tile each: overlap i is Gaussian i's
  }
  bins.tile_start = {0, std::uint32_t(n)};
  RenderResult result;
  result.resize(kTileSize, kTileSize);
  blend_tiles(projected, bins, grid, kBackground, /*for_backward=*/true, result);

  const std::size_t p = std::size_t(kPixelY) * kTileSize + kPixelX;
  Outcome o{{result.color.data[3 * p], result.color.data[3 * p + 1], result.color.data[3 * p + 2]},
            result.alpha[p], result.depth[p], result.final_transmittance[p],
            result.contributor_count[p], std::vector<float>(n), std::vector<float>(3 * n), {}};
  Image v_image(kTileSize, kTileSize, 3);
  for (int c = 0; c < 3; ++c) v_image.at(kPixelX, kPixelY, c) = v_color[c];
  OverlapGradients grads;
  blend_tiles_backward(projected, bins, grid, kBackground, AlphaClampGradient::kZero, result,
                       v_image, grads);
  for (std::size_t i = 0; i < n; ++i) {
    const Splat2DGrad record = grads.written(i) ? grads.records[i].grad : Splat2DGrad{};  // unwritten: zero
    o.v_alpha[i] = record.opacity;  // = G·∂L/∂α with G = 1
    for (int c = 0; c < 3; ++c) o.v_rgb[3 * i + c] = record.color[c];
  }
  return o;
}

// The size of the terms ∂L/∂αᵢ = Tᵢ (v·cᵢ − v·Bᵢ) − T_N/(1 − αᵢ) · v·bg is formed from
// (composite.hpp): each is at most Tᵢ Σ|v_c| (colours, Bᵢ and bg lie in [0, 1], and
// T_N/(1 − αᵢ) ≤ Tᵢ). A rounding in those terms moves the difference by a multiple of
// FLT_EPSILON times this, however small the difference itself is.
float v_alpha_term_scale(const Sequence& s, const Outcome& nerf, std::size_t i,
                         const float v_color[3]) {
  const float transmittance = nerf.weights[i] / s.alpha[i];  // Tᵢ
  return transmittance * (std::fabs(v_color[0]) + std::fabs(v_color[1]) + std::fabs(v_color[2]));
}

// Same code, same inputs, same operation order; the one freedom left is the compiler's: with
// GCC's default -ffp-contract=fast (GNU mode, FMA on -march=native) it fuses a·b + c into
// one rounding at its own discretion per inlining context, and it does so differently in the
// scalar (float, bool) and the kLanes-wide instantiation: colour sums then differ in the last
// bit (built with -ffp-contract=off the two agree bit for bit). So sums of positive terms are
// compared to 4 ulps (EXPECT_FLOAT_EQ) and the counts exactly. ∂L/∂α is a difference of
// nearly equal terms, so a last-bit change in them can be many ulps of the result (on an
// AMD family 26 CPU: up to 22 ulps near 10⁻⁴, and 5·10⁻⁸ at 0.11, though at most 0.45
// FLT_EPSILON of the terms' size). It is compared to 4 FLT_EPSILON of its terms' size:
// about 9 times what that CPU shows, and at most 1.2·10⁻⁶ here.
void expect_identical(const Sequence& s, const float v_color[3], const char* what) {
  const Outcome nerf = through_nerf(s, v_color);
  const Outcome splat = through_rasterizer(s, v_color);
  for (int c = 0; c < 3; ++c)
    EXPECT_FLOAT_EQ(nerf.color[c], splat.color[c]) << what << " channel " << c;
  EXPECT_FLOAT_EQ(nerf.alpha, splat.alpha) << what;
  EXPECT_FLOAT_EQ(nerf.depth, splat.depth) << what;
  EXPECT_FLOAT_EQ(nerf.final_transmittance, splat.final_transmittance) << what;
  EXPECT_EQ(nerf.blended, splat.blended) << what;  // the same early stop
  for (std::size_t i = 0; i < s.size(); ++i) {
    const float tolerance = 4.0f * FLT_EPSILON * v_alpha_term_scale(s, nerf, i, v_color);
    EXPECT_NEAR(nerf.v_alpha[i], splat.v_alpha[i], tolerance) << what << " sample " << i;
    for (int c = 0; c < 3; ++c)
      EXPECT_FLOAT_EQ(nerf.v_rgb[3 * i + c], splat.v_rgb[3 * i + c]) << what << " sample " << i;
  }
  // Not vacuous: something was blended and has gradient.
  EXPECT_GT(nerf.blended, 2u) << what;
  EXPECT_NE(nerf.v_alpha[0], 0.0f) << what;
}

TEST(CompositorShared, NerfRayAndSplatPixelAgree) {
  const float v_color[3] = {0.7f, -1.3f, 0.4f};
  int complete = 0;  // sequences blended to the end, with T_N·bg in the colour
  for (unsigned seed = 1; seed <= 8; ++seed) {
    const Sequence s = make_sequence(6, seed, false);
    complete += through_nerf(s, v_color).blended == s.size();
    expect_identical(s, v_color, "translucent");
  }
  EXPECT_GE(complete, 4);
}

TEST(CompositorShared, NerfRayAndSplatPixelAgreeThroughTheEarlyStop) {
  const float v_color[3] = {-0.2f, 0.9f, 1.1f};
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const Sequence s = make_sequence(30, seed, true);
    const Outcome nerf = through_nerf(s, v_color);
    ASSERT_LT(nerf.blended, s.size()) << "the sequence must reach the T floor";
    expect_identical(s, v_color, "terminating");
  }
}

}  // namespace
}  // namespace splat
