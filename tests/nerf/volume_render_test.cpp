// The NeRF volume-rendering step: forward against a hand-computed ray, backward against
// central differences in double (per ray, the templated code), the batched float version
// against the double reference, early termination, thread-count invariance.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <span>
#include <tbb/global_control.h>
#include <vector>

#include "tests/gradient_check.hpp"
#include "splat/core/error.hpp"
#include "splat/nerf/ray_composite.hpp"
#include "splat/nerf/volume_render.hpp"

namespace splat {
namespace {

constexpr float kBackground[3] = {0.2f, 0.5f, 0.9f};
constexpr double kBackgroundD[3] = {0.2, 0.5, 0.9};

TEST(NerfVolume, ForwardMatchesAHandComputedThreeSampleRay) {
  const std::vector<std::uint32_t> offsets = {0, 3};
  const std::vector<float> t = {1.0f, 1.5f, 1.75f}, delta = {0.5f, 0.25f, 1.0f};
  const std::vector<float> sigma = {0.5f, 2.0f, 1.0f};
  const std::vector<float> rgb = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  VolumeRenderResult out;
  volume_render({offsets, t, delta}, sigma, rgb, kBackground, out);
  // σδ = 0.25, 0.5, 1: α = 1 − e^−0.25, 1 − e^−0.5, 1 − e^−1; T = 1, e^−0.25, e^−0.75;
  // T_N = e^−1.75.
  const double a0 = 1 - std::exp(-0.25), a1 = 1 - std::exp(-0.5), a2 = 1 - std::exp(-1.0);
  const double w0 = a0, w1 = std::exp(-0.25) * a1, w2 = std::exp(-0.75) * a2;
  const double tn = std::exp(-1.75);
  EXPECT_NEAR(out.color[0], w0 + tn * kBackgroundD[0], 1e-6);
  EXPECT_NEAR(out.color[1], w1 + tn * kBackgroundD[1], 1e-6);
  EXPECT_NEAR(out.color[2], w2 + tn * kBackgroundD[2], 1e-6);
  EXPECT_NEAR(out.alpha[0], 1 - tn, 1e-6);
  EXPECT_NEAR(out.final_transmittance[0], tn, 1e-6);
  EXPECT_NEAR(out.depth[0], w0 * 1.0 + w1 * 1.5 + w2 * 1.75, 1e-6);
  EXPECT_NEAR(out.weights[0], w0, 1e-6);
  EXPECT_NEAR(out.weights[1], w1, 1e-6);
  EXPECT_NEAR(out.weights[2], w2, 1e-6);
  EXPECT_NEAR(out.sample_alpha[1], a1, 1e-7);
  EXPECT_EQ(out.blended_count[0], 3u);
}

// One ray in double: x = [σᵢ, rᵢ, gᵢ, bᵢ] per sample → the composited colour.
struct DoubleRay {
  std::vector<double> t, delta;

  std::vector<double> render(const std::vector<double>& x, RayComposite<double>* saved = nullptr,
                             std::vector<double>* alpha_out = nullptr) const {
    const std::size_t n = t.size();
    std::vector<double> alpha(n), rgb(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
      alpha[i] = density_to_alpha(x[4 * i], delta[i]);
      for (int c = 0; c < 3; ++c) rgb[3 * i + c] = x[4 * i + 1 + c];
    }
    const RayComposite<double> r = composite_ray(n, alpha.data(), rgb.data(), t.data(),
                                                 kBackgroundD, static_cast<double*>(nullptr));
    if (saved) *saved = r;
    if (alpha_out) *alpha_out = alpha;
    return {r.color[0], r.color[1], r.color[2]};
  }

  // The analytic vᵀJ through composite_ray_vjp and density_to_alpha_vjp.
  std::vector<double> vjp(const std::vector<double>& x, const std::vector<double>& v) const {
    const std::size_t n = t.size();
    RayComposite<double> saved;
    std::vector<double> alpha;
    render(x, &saved, &alpha);
    std::vector<double> rgb(3 * n), v_alpha(n), v_rgb(3 * n), grad(4 * n);
    for (std::size_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) rgb[3 * i + c] = x[4 * i + 1 + c];
    composite_ray_vjp(n, alpha.data(), rgb.data(), saved, kBackgroundD, v.data(), v_alpha.data(),
                      v_rgb.data());
    for (std::size_t i = 0; i < n; ++i) {
      grad[4 * i] = density_to_alpha_vjp(x[4 * i], delta[i], v_alpha[i]);
      for (int c = 0; c < 3; ++c) grad[4 * i + 1 + c] = v_rgb[3 * i + c];
    }
    return grad;
  }
};

DoubleRay ray_with_lengths(const std::vector<double>& delta) {
  DoubleRay ray{{}, delta};
  double t = 1.0;
  for (double d : delta) {
    ray.t.push_back(t);
    t += d;
  }
  return ray;
}

// A solid surface: one sample with σδ = 50 would take T below the floor at once, and the
// shared early stop would then skip it (the ray showing the background). With α capped at
// 0.99 it is blended, and its neighbour behind it too: the surface shows.
TEST(NerfVolume, OpaqueSampleIsCappedAndTheSurfaceShows) {
  EXPECT_FLOAT_EQ(density_to_alpha(50.0f, 1.0f), 0.99f);
  EXPECT_EQ(density_to_alpha_vjp(50.0f, 1.0f, 1.0f), 0.0f);  // clamped: no gradient
  EXPECT_GT(density_to_alpha_vjp(1.0f, 1.0f, 1.0f), 0.0f);
  const std::vector<std::uint32_t> offsets = {0, 3};
  const std::vector<float> t = {1.0f, 2.0f, 3.0f}, delta = {1.0f, 1.0f, 1.0f};
  const std::vector<float> sigma = {50.0f, 50.0f, 50.0f};
  const std::vector<float> rgb = {0.2f, 0.4f, 0.6f, 0.2f, 0.4f, 0.6f, 0.9f, 0.9f, 0.9f};
  VolumeRenderResult out;
  volume_render({offsets, t, delta}, sigma, rgb, kBackground, out);
  EXPECT_GE(out.blended_count[0], 1u);
  EXPECT_LE(out.final_transmittance[0], 0.01f);
  EXPECT_NEAR(out.color[0], 0.2, 0.01);
  EXPECT_NEAR(out.color[2], 0.6, 0.01);
}

TEST(NerfVolume, BackwardMatchesFiniteDifferencesInDouble) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const int n = 7;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> length(0.05, 0.4), density(0.0, 4.0);
    std::vector<double> delta(n);
    for (double& d : delta) d = length(rng);
    const DoubleRay ray = ray_with_lengths(delta);
    std::vector<double> x = test::random_vector(4 * n, seed + 10);
    for (int i = 0; i < n; ++i) x[4 * i] = density(rng);
    const std::vector<double> v = test::random_vector(3, seed + 20);
    RayComposite<double> saved;
    ray.render(x, &saved);
    ASSERT_EQ(saved.blended_count, std::uint32_t(n));  // no early stop in this test
    test::expect_vjp_matches([&](const std::vector<double>& in) { return ray.render(in); }, x, v,
                             ray.vjp(x, v), "volume render", 1e-6, 1e-8, seed);
  }
}

TEST(NerfVolume, RayThatReachesTheTransmittanceFloorStopsAndBackpropagatesThroughItsPrefix) {
  // σδ = 3 per sample: T = e^−3k; e^−9 = 1.2e-4 ≥ 1e-4 but e^−12 = 6e-6 < 1e-4, so the
  // fourth sample (index 3) would drop T below the floor: three are blended, six are not.
  const int n = 9;
  const DoubleRay ray = ray_with_lengths(std::vector<double>(n, 0.5));
  std::vector<double> x = test::random_vector(4 * n, 7);
  for (int i = 0; i < n; ++i) x[4 * i] = 6.0;
  RayComposite<double> saved;
  ray.render(x, &saved);
  EXPECT_EQ(saved.blended_count, 3u);
  EXPECT_NEAR(saved.final_transmittance, std::exp(-9.0), 1e-15);
  const std::vector<double> v = test::random_vector(3, 8);
  const std::vector<double> grad = ray.vjp(x, v);
  for (int i = 3; i < n; ++i)
    for (int k = 0; k < 4; ++k) EXPECT_EQ(grad[4 * i + k], 0.0) << "sample " << i;
  // Small perturbations keep the stop where it is, so the derivative is the prefix's.
  test::expect_vjp_matches([&](const std::vector<double>& in) { return ray.render(in); }, x, v,
                           grad, "terminated ray", 1e-6, 1e-8);
  // The batched float path agrees: weights past the stop are zero.
  std::vector<std::uint32_t> offsets = {0, std::uint32_t(n)};
  std::vector<float> t(n), delta(n, 0.5f), sigma(n, 6.0f), rgb(3 * n);
  for (int i = 0; i < n; ++i) {
    t[i] = float(ray.t[i]);
    for (int c = 0; c < 3; ++c) rgb[3 * i + c] = float(x[4 * i + 1 + c]);
  }
  VolumeRenderResult out;
  volume_render({offsets, t, delta}, sigma, rgb, kBackground, out);
  EXPECT_EQ(out.blended_count[0], 3u);
  for (int i = 3; i < n; ++i) EXPECT_EQ(out.weights[i], 0.0f);
}

// A batch of random rays of varying length (some empty), float.
struct Batch {
  std::vector<std::uint32_t> offsets{0};
  std::vector<float> t, delta, sigma, rgb, v_color;

  Batch(int rays, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> count(0, 40);
    std::uniform_real_distribution<float> length(0.01f, 0.2f), density(0.0f, 20.0f), unit(0, 1);
    std::normal_distribution<float> normal;
    for (int r = 0; r < rays; ++r) {
      const int n = r == 1 ? 0 : count(rng);  // ray 1 has no samples
      float position = 2.0f;
      for (int i = 0; i < n; ++i) {
        t.push_back(position);
        delta.push_back(length(rng));
        position += delta.back();
        sigma.push_back(density(rng));
        for (int c = 0; c < 3; ++c) rgb.push_back(unit(rng));
      }
      offsets.push_back(std::uint32_t(t.size()));
      for (int c = 0; c < 3; ++c) v_color.push_back(normal(rng));
    }
  }
  RaySampleBatch samples() const { return {offsets, t, delta}; }
};

struct BatchGradients {
  VolumeRenderResult forward;
  std::vector<float> v_sigma, v_rgb;
};

BatchGradients run(const Batch& b) {
  BatchGradients g;
  volume_render(b.samples(), b.sigma, b.rgb, kBackground, g.forward);
  g.v_sigma.assign(b.sigma.size(), -1.0f);
  g.v_rgb.assign(b.rgb.size(), -1.0f);
  volume_render_backward(b.samples(), b.sigma, b.rgb, kBackground, g.forward, b.v_color,
                         g.v_sigma, g.v_rgb);
  return g;
}

TEST(NerfVolume, BatchedFloatMatchesThePerRayDoubleReference) {
  const Batch b(300, 3);
  const BatchGradients g = run(b);
  int terminated = 0;
  for (std::size_t r = 0; r + 1 < b.offsets.size(); ++r) {
    const std::size_t begin = b.offsets[r], n = b.offsets[r + 1] - begin;
    DoubleRay ray{std::vector<double>(b.t.begin() + begin, b.t.begin() + begin + n),
                  std::vector<double>(b.delta.begin() + begin, b.delta.begin() + begin + n)};
    std::vector<double> x(4 * n);
    for (std::size_t i = 0; i < n; ++i) {
      x[4 * i] = b.sigma[begin + i];
      for (int c = 0; c < 3; ++c) x[4 * i + 1 + c] = b.rgb[3 * (begin + i) + c];
    }
    RayComposite<double> saved;
    const std::vector<double> color = ray.render(x, &saved);
    // Near-floor rays may stop one sample apart in float and double; skip those few.
    if (saved.blended_count != g.forward.blended_count[r]) continue;
    terminated += saved.blended_count < n;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(g.forward.color[3 * r + c], color[c], 2e-6) << r;
    EXPECT_NEAR(g.forward.depth[r], saved.depth, 2e-5) << r;
    const std::vector<double> v = {b.v_color[3 * r], b.v_color[3 * r + 1], b.v_color[3 * r + 2]};
    const std::vector<double> grad = ray.vjp(x, v);
    for (std::size_t i = 0; i < n; ++i) {
      EXPECT_NEAR(g.v_sigma[begin + i], grad[4 * i], 1e-5 + 1e-4 * std::abs(grad[4 * i])) << r;
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(g.v_rgb[3 * (begin + i) + c], grad[4 * i + 1 + c], 1e-6) << r;
    }
  }
  EXPECT_GT(terminated, 20);  // the batch exercises the early stop
  // The empty ray shows the background.
  for (int c = 0; c < 3; ++c) EXPECT_EQ(g.forward.color[3 + c], kBackground[c]);
  EXPECT_EQ(g.forward.alpha[1], 0.0f);
}

TEST(NerfVolume, BitIdenticalForAnyThreadCount) {
  const Batch b(2000, 4);
  BatchGradients runs[2];
  const int threads[2] = {1, 2};
  for (int i = 0; i < 2; ++i) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads[i]);
    runs[i] = run(b);
  }
  EXPECT_EQ(runs[0].forward.color, runs[1].forward.color);
  EXPECT_EQ(runs[0].forward.depth, runs[1].forward.depth);
  EXPECT_EQ(runs[0].forward.weights, runs[1].forward.weights);
  EXPECT_EQ(runs[0].v_sigma, runs[1].v_sigma);
  EXPECT_EQ(runs[0].v_rgb, runs[1].v_rgb);
}

// Random colours, one per ray of `b`.
std::vector<float> random_backgrounds(const Batch& b, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0, 1);
  std::vector<float> backgrounds(3 * (b.offsets.size() - 1));
  for (float& v : backgrounds) v = unit(rng);
  return backgrounds;
}

TEST(NerfVolume, PerRayBackgroundsRenderEachRayAsItsOwnColourAlone) {
  const Batch b(200, 6);
  const std::vector<float> backgrounds = random_backgrounds(b, 7);
  BatchGradients g;
  volume_render(b.samples(), b.sigma, b.rgb, RayBackgrounds(std::span(backgrounds)), g.forward);
  g.v_sigma.assign(b.sigma.size(), -1.0f);
  g.v_rgb.assign(b.rgb.size(), -1.0f);
  volume_render_backward(b.samples(), b.sigma, b.rgb, RayBackgrounds(std::span(backgrounds)), g.forward,
                         b.v_color, g.v_sigma, g.v_rgb);
  for (std::size_t r = 0; r + 1 < b.offsets.size(); ++r) {
    // Ray r on its own, its colour the batch's one background: the same values, bit for bit.
    const std::size_t begin = b.offsets[r], end = b.offsets[r + 1];
    const std::vector<std::uint32_t> offsets = {0, std::uint32_t(end - begin)};
    const std::span<const float> t(b.t.data() + begin, end - begin), delta(b.delta.data() + begin, end - begin),
        sigma(b.sigma.data() + begin, end - begin), rgb(b.rgb.data() + 3 * begin, 3 * (end - begin)),
        v_color(b.v_color.data() + 3 * r, 3);
    VolumeRenderResult alone;
    volume_render({offsets, t, delta}, sigma, rgb, &backgrounds[3 * r], alone);
    std::vector<float> v_sigma(end - begin), v_rgb(3 * (end - begin));
    volume_render_backward({offsets, t, delta}, sigma, rgb, &backgrounds[3 * r], alone, v_color, v_sigma, v_rgb);
    for (int c = 0; c < 3; ++c) ASSERT_EQ(g.forward.color[3 * r + c], alone.color[c]) << r;
    for (std::size_t i = 0; i < end - begin; ++i) {
      ASSERT_EQ(g.v_sigma[begin + i], v_sigma[i]) << r;
      for (int c = 0; c < 3; ++c) ASSERT_EQ(g.v_rgb[3 * (begin + i) + c], v_rgb[3 * i + c]) << r;
    }
  }
  // The empty ray shows its own colour.
  for (int c = 0; c < 3; ++c) EXPECT_EQ(g.forward.color[3 + c], backgrounds[3 + c]);
}

TEST(NerfVolume, PerRayBackgroundDensityGradientMatchesFiniteDifferences) {
  // L = Σ v·colour with a colour per ray: ∂L/∂σ carries each ray's own background through
  // T_N. Thin densities (σδ ≤ 0.8) keep every ray clear of the α cap and the early stop,
  // where the function has kinks that a central difference would straddle.
  Batch b(40, 8);
  for (std::size_t i = 0; i < b.sigma.size(); ++i) b.sigma[i] = b.sigma[i] * 0.2f;
  const std::vector<float> backgrounds = random_backgrounds(b, 9);
  const RayBackgrounds each{std::span<const float>(backgrounds)};
  VolumeRenderResult forward;
  volume_render(b.samples(), b.sigma, b.rgb, each, forward);
  std::vector<float> v_sigma(b.sigma.size()), v_rgb(b.rgb.size());
  volume_render_backward(b.samples(), b.sigma, b.rgb, each, forward, b.v_color, v_sigma, v_rgb);
  const auto loss = [&](const std::vector<float>& sigma) {
    VolumeRenderResult out;
    volume_render(b.samples(), sigma, b.rgb, each, out);
    double sum = 0;
    for (std::size_t i = 0; i < out.color.size(); ++i) sum += double(b.v_color[i]) * out.color[i];
    return sum;
  };
  std::vector<bool> stopped_early(b.sigma.size(), false);  // its ray hit the T floor: skip
  for (std::size_t r = 0; r + 1 < b.offsets.size(); ++r)
    for (std::uint32_t i = b.offsets[r]; i < b.offsets[r + 1]; ++i)
      stopped_early[i] = forward.blended_count[r] < b.offsets[r + 1] - b.offsets[r];
  int checked = 0;
  for (std::size_t i = 0; i < b.sigma.size(); i += 7) {
    if (stopped_early[i]) continue;
    constexpr float kStep = 1e-2f;
    std::vector<float> plus = b.sigma, minus = b.sigma;
    plus[i] += kStep;
    minus[i] -= kStep;
    if (minus[i] < 0) continue;
    const double numeric = (loss(plus) - loss(minus)) / (double(plus[i]) - double(minus[i]));
    EXPECT_NEAR(v_sigma[i], numeric, 2e-4 + 2e-3 * std::abs(numeric)) << "sample " << i;
    ++checked;
  }
  EXPECT_GT(checked, 20);
  // The gradient depends on the background: with all rays on one colour it differs.
  std::vector<float> v_sigma_shared(b.sigma.size()), v_rgb_shared(b.rgb.size());
  volume_render(b.samples(), b.sigma, b.rgb, kBackground, forward);
  volume_render_backward(b.samples(), b.sigma, b.rgb, kBackground, forward, b.v_color, v_sigma_shared,
                         v_rgb_shared);
  EXPECT_NE(v_sigma, v_sigma_shared);
}

TEST(NerfVolume, RejectsInconsistentInputs) {
  Batch b(4, 5);
  VolumeRenderResult out;
  std::vector<float> short_sigma(b.sigma.begin(), b.sigma.end() - 1);
  EXPECT_THROW(volume_render(b.samples(), short_sigma, b.rgb, kBackground, out), ArgumentError);
  std::vector<std::uint32_t> bad_offsets = b.offsets;
  bad_offsets.back() += 1;
  EXPECT_THROW(volume_render({bad_offsets, b.t, b.delta}, b.sigma, b.rgb, kBackground, out),
               ArgumentError);
  EXPECT_THROW(volume_render({{}, b.t, b.delta}, b.sigma, b.rgb, kBackground, out),
               ArgumentError);
  const std::vector<float> three_colours(9, 0.5f);  // for 4 rays
  EXPECT_THROW(volume_render(b.samples(), b.sigma, b.rgb, RayBackgrounds(std::span(three_colours)), out),
               ArgumentError);
  volume_render(b.samples(), b.sigma, b.rgb, kBackground, out);
  std::vector<float> v_sigma(b.sigma.size()), v_rgb(b.rgb.size());
  std::vector<float> short_v_color(b.v_color.begin(), b.v_color.end() - 1);
  EXPECT_THROW(volume_render_backward(b.samples(), b.sigma, b.rgb, kBackground, out,
                                      short_v_color, v_sigma, v_rgb),
               ArgumentError);
}

}  // namespace
}  // namespace splat
