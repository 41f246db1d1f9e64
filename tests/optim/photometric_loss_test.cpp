#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include "splat/core/error.hpp"
#include "splat/optim/photometric_loss.hpp"
#include "splat/optim/ssim.hpp"

namespace splat {
namespace {

// Values uniform in [lo, hi), [height, width, channels].
std::vector<double> random_values(int width, int height, int channels, unsigned seed,
                                  double lo = 0.0, double hi = 1.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  std::vector<double> v(std::size_t(width) * height * channels);
  for (double& x : v) x = u(rng);
  return v;
}

Image to_image(const std::vector<double>& v, int width, int height, int channels) {
  Image image(width, height, channels);
  for (std::size_t i = 0; i < v.size(); ++i) image.data[i] = float(v[i]);
  return image;
}

// The oracle: SSIM straight from its definition, in double, with a direct 2D 11×11 convolution
// (no separability) whose out-of-image taps read zero, as conv2d with padding 5 does.
double naive_ssim(const std::vector<double>& x, const std::vector<double>& y, int width,
                  int height, int channels) {
  constexpr int kRadius = 5;
  double g[2 * kRadius + 1], total = 0;
  for (int i = -kRadius; i <= kRadius; ++i) total += g[i + kRadius] = std::exp(-i * i / 4.5);
  for (double& v : g) v /= total;
  const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
  double sum = 0;
  for (int c = 0; c < channels; ++c)
    for (int py = 0; py < height; ++py)
      for (int px = 0; px < width; ++px) {
        double mu1 = 0, mu2 = 0, e11 = 0, e22 = 0, e12 = 0;
        for (int dy = -kRadius; dy <= kRadius; ++dy)
          for (int dx = -kRadius; dx <= kRadius; ++dx) {
            const int qx = px + dx, qy = py + dy;
            if (qx < 0 || qy < 0 || qx >= width || qy >= height) continue;
            const double w = g[dy + kRadius] * g[dx + kRadius];
            const std::size_t i = (std::size_t(qy) * width + qx) * channels + c;
            mu1 += w * x[i];
            mu2 += w * y[i];
            e11 += w * x[i] * x[i];
            e22 += w * y[i] * y[i];
            e12 += w * x[i] * y[i];
          }
        const double s11 = e11 - mu1 * mu1, s22 = e22 - mu2 * mu2, s12 = e12 - mu1 * mu2;
        sum += (2 * mu1 * mu2 + c1) * (2 * s12 + c2) /
               ((mu1 * mu1 + mu2 * mu2 + c1) * (s11 + s22 + c2));
      }
  return sum / (double(width) * height * channels);
}

double loss_in_double(const std::vector<double>& rendered, const std::vector<double>& target,
                      int width, int height, double lambda, std::vector<double>* gradient,
                      std::vector<double>& buffers) {
  if (gradient) gradient->assign(rendered.size(), 0.0);
  return photometric_loss_core<double>(rendered.data(), target.data(), width, height, lambda,
                                       gradient ? gradient->data() : nullptr, buffers)
      .loss;
}

// A pair for gradient checks: |rendered − target| ≥ 0.05 everywhere, so finite differences of
// step ≪ 0.05 never cross L1's kink.
void pair_away_from_the_kink(int width, int height, unsigned seed, std::vector<double>& rendered,
                             std::vector<double>& target) {
  rendered = random_values(width, height, 3, seed, 0.05, 0.95);
  target = random_values(width, height, 3, seed + 1, 0.05, 0.95);
  for (std::size_t i = 0; i < rendered.size(); ++i)
    if (std::abs(rendered[i] - target[i]) < 0.05) target[i] = rendered[i] + (target[i] < 0.5 ? 0.05 : -0.05);
}

TEST(Ssim, OfAnImageWithItselfIsOne) {
  const Image a = to_image(random_values(37, 29, 3, 1), 37, 29, 3);
  EXPECT_NEAR(ssim(a, a), 1.0, 1e-6);
}

TEST(Ssim, IsSymmetric) {
  const Image a = to_image(random_values(31, 26, 3, 2), 31, 26, 3);
  const Image b = to_image(random_values(31, 26, 3, 3), 31, 26, 3);
  const double ab = ssim(a, b);
  EXPECT_LT(ab, 0.5);  // unrelated noise images are far from similar
  EXPECT_NEAR(ab, ssim(b, a), 1e-7);
}

TEST(Ssim, DecreasesAsNoiseGrows) {
  constexpr int kW = 48, kH = 40;
  Image clean(kW, kH, 3);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      for (int c = 0; c < 3; ++c)
        clean.at(x, y, c) = 0.5f + 0.3f * std::sin(0.3f * x + 0.2f * y + float(c));
  const std::vector<double> noise = random_values(kW, kH, 3, 4, -1.0, 1.0);
  double previous = ssim(clean, clean);
  for (const double amplitude : {0.01, 0.03, 0.1, 0.3}) {
    Image noisy = clean;
    for (std::size_t i = 0; i < noise.size(); ++i) noisy.data[i] += float(amplitude * noise[i]);
    const double value = ssim(clean, noisy);
    EXPECT_LT(value, previous) << "amplitude " << amplitude;
    previous = value;
  }
  EXPECT_LT(previous, 0.5);
}

TEST(Ssim, MatchesTheNaiveReferenceWhereBordersDominate) {
  // 23×17: every pixel is within a window of the border, so the zero padding shapes the result.
  // The implementation works in tiles of 64×64 pixels; 64×48 is one whole tile, 130×70 spans
  // six, and the tiny sizes are smaller than the window in one or both directions.
  for (const auto& [w, h] : {std::pair{23, 17}, std::pair{64, 48}, std::pair{130, 70},
                             std::pair{1, 1}, std::pair{5, 3}, std::pair{40, 2},
                             std::pair{2, 37}}) {
    const std::vector<double> x = random_values(w, h, 3, 5), y = random_values(w, h, 3, 6);
    const double reference = naive_ssim(x, y, w, h, 3);
    EXPECT_NEAR(ssim(to_image(x, w, h, 3), to_image(y, w, h, 3)), reference, 1e-5)
        << w << "x" << h;
    // The double instantiation differs from the oracle by rounding only.
    std::vector<double> buffers;
    EXPECT_NEAR(ssim_forward<double>(x.data(), y.data(), SsimShape{w, h, 3}, false, buffers),
                reference, 1e-13)
        << w << "x" << h;
  }
}

TEST(Ssim, MatchesTheNaiveReferenceOnCorrelatedImagesAndOtherChannelCounts) {
  // A correlated pair (SSIM near 0.9) and 1 and 4 channels, which the metric accepts.
  for (const int channels : {1, 3, 4}) {
    const int w = 30, h = 21;
    const std::vector<double> x = random_values(w, h, channels, 7);
    std::vector<double> y = random_values(w, h, channels, 8, -0.1, 0.1);
    for (std::size_t i = 0; i < y.size(); ++i) y[i] += x[i];
    const double reference = naive_ssim(x, y, w, h, channels);
    EXPECT_GT(reference, 0.8);
    EXPECT_NEAR(ssim(to_image(x, w, h, channels), to_image(y, w, h, channels)), reference, 1e-5)
        << channels << " channels";
  }
}

TEST(PhotometricLoss, IsZeroForEqualImagesWithAVanishingGradient) {
  const Image a = to_image(random_values(40, 30, 3, 9), 40, 30, 3);
  SsimScratch scratch;
  Image v;
  const LossValue value = photometric_loss(a, a, kDefaultSsimWeight, &v, scratch);
  EXPECT_EQ(value.l1, 0.0);
  EXPECT_NEAR(value.ssim, 1.0, 1e-6);
  EXPECT_NEAR(value.loss, 0.0, 1e-6);
  ASSERT_EQ(v.width, 40);
  ASSERT_EQ(v.height, 30);
  ASSERT_EQ(v.channels, 3);
  // SSIM is at its maximum, and L1's derivative is taken as 0 at the kink.
  for (const float g : v.data) EXPECT_NEAR(g, 0.0f, 1e-9f);
}

TEST(PhotometricLoss, CombinesL1AndSsimWithTheWeight) {
  const int w = 33, h = 19;
  const Image a = to_image(random_values(w, h, 3, 10), w, h, 3);
  const Image b = to_image(random_values(w, h, 3, 11), w, h, 3);
  double l1 = 0;
  for (std::size_t i = 0; i < a.data.size(); ++i) l1 += std::abs(double(a.data[i]) - b.data[i]);
  l1 /= double(a.data.size());
  SsimScratch scratch;
  for (const float lambda : {0.0f, 0.2f, 1.0f}) {
    const LossValue value = photometric_loss(a, b, lambda, nullptr, scratch);
    EXPECT_NEAR(value.l1, l1, 1e-12);
    EXPECT_EQ(value.ssim, ssim(a, b));
    const double weight = lambda;  // the weighting is done in double
    EXPECT_NEAR(value.loss, (1 - weight) * l1 + weight * (1 - value.ssim), 1e-12);
  }
}

// Central differences of the double loss against the analytic gradient, element by element,
// relative error ≤ 1e-4 on each. Step 1e-5: truncation O(h²·L''') and rounding O(ε·L/h) stay
// near 1e-11 in absolute terms (measured: worst relative error 5e-7, smallest element 2e-6),
// while a wrong term changes elements by their own size. `elements` lists the ones checked;
// empty means all.
void expect_gradient_matches_differences(double lambda, int width, int height,
                                         std::vector<std::size_t> elements = {}) {
  std::vector<double> rendered, target, gradient, buffers;
  pair_away_from_the_kink(width, height, 12, rendered, target);
  loss_in_double(rendered, target, width, height, lambda, &gradient, buffers);
  constexpr double kStep = 1e-5;
  double max_abs = 0;
  for (const double g : gradient) max_abs = std::max(max_abs, std::abs(g));
  ASSERT_GT(max_abs, 1e-4 / (double(width) * height));  // a gradient that is not all zero
  if (elements.empty())
    for (std::size_t i = 0; i < rendered.size(); ++i) elements.push_back(i);
  for (const std::size_t i : elements) {
    std::vector<double> shifted = rendered;
    shifted[i] = rendered[i] + kStep;
    const double up = loss_in_double(shifted, target, width, height, lambda, nullptr, buffers);
    shifted[i] = rendered[i] - kStep;
    const double down = loss_in_double(shifted, target, width, height, lambda, nullptr, buffers);
    const double numeric = (up - down) / (2 * kStep);
    EXPECT_NEAR(gradient[i], numeric, 1e-4 * std::abs(numeric))
        << "element " << i << " (pixel " << i / 3 % width << "," << i / 3 / width << " channel "
        << i % 3 << ") of " << width << "x" << height << ", lambda " << lambda;
  }
}

TEST(PhotometricLoss, GradientMatchesCentralDifferences) {
  expect_gradient_matches_differences(kDefaultSsimWeight, 13, 11);
  expect_gradient_matches_differences(kDefaultSsimWeight, 7, 35);
}

TEST(PhotometricLoss, GradientMatchesCentralDifferencesAcrossTiles) {
  // The implementation works in tiles of 64×64 pixels, each blurring its rows and columns with
  // a halo of 5 read from its neighbours: 70×69 crosses a tile edge in both directions. Every
  // channel of the pixels beside the edges, the corner where four tiles meet, and the image's
  // own corners is checked (all of them would take minutes).
  constexpr int kW = 70, kH = 69;
  std::vector<std::size_t> elements;
  for (const int y : {0, 58, 63, 64, 69 - 1})
    for (const int x : {0, 59, 63, 64, 68, 70 - 1})
      for (int c = 0; c < 3; ++c) elements.push_back((std::size_t(y) * kW + x) * 3 + c);
  for (const double lambda : {double(kDefaultSsimWeight), 1.0})
    expect_gradient_matches_differences(lambda, kW, kH, elements);
}

TEST(PhotometricLoss, SsimGradientAloneMatchesCentralDifferences) {
  // λ = 1: no L1 term to dominate.
  expect_gradient_matches_differences(1.0, 13, 11);
  expect_gradient_matches_differences(1.0, 7, 35);
}

TEST(PhotometricLoss, DirectionalDerivativeMatchesTheGradient) {
  // ⟨∂L/∂x, δ⟩ against (L(x + εδ) − L(x − εδ)) / 2ε for random directions δ, on an image that
  // spans four of the implementation's 64×64 tiles.
  constexpr int kW = 75, kH = 81;
  std::vector<double> rendered, target, gradient, buffers;
  pair_away_from_the_kink(kW, kH, 13, rendered, target);
  for (const double lambda : {0.2, 1.0}) {
    loss_in_double(rendered, target, kW, kH, lambda, &gradient, buffers);
    for (unsigned seed = 0; seed < 4; ++seed) {
      const std::vector<double> delta = random_values(kW, kH, 3, 100 + seed, -1.0, 1.0);
      constexpr double kEps = 1e-6;  // |εδ| ≤ 1e-6 ≪ 0.05, the distance to L1's kink
      std::vector<double> up = rendered, down = rendered;
      double dot = 0;
      for (std::size_t i = 0; i < rendered.size(); ++i) {
        up[i] += kEps * delta[i];
        down[i] -= kEps * delta[i];
        dot += gradient[i] * delta[i];
      }
      const double numeric = (loss_in_double(up, target, kW, kH, lambda, nullptr, buffers) -
                              loss_in_double(down, target, kW, kH, lambda, nullptr, buffers)) /
                             (2 * kEps);
      EXPECT_NEAR(dot, numeric, 1e-6 * std::abs(numeric)) << "lambda " << lambda;
    }
  }
}

TEST(PhotometricLoss, FloatGradientAgreesWithDouble) {
  // The float path training runs is the double path up to rounding.
  constexpr int kW = 41, kH = 29;
  std::vector<double> rendered, target, gradient, buffers;
  pair_away_from_the_kink(kW, kH, 14, rendered, target);
  const double expected = loss_in_double(rendered, target, kW, kH, 0.2, &gradient, buffers);
  SsimScratch scratch;
  Image v;
  const LossValue value = photometric_loss(to_image(rendered, kW, kH, 3),
                                           to_image(target, kW, kH, 3), 0.2f, &v, scratch);
  // Inputs are rounded to float, so the values agree to float precision, not better.
  EXPECT_NEAR(value.loss, expected, 1e-6);
  double error2 = 0, norm2 = 0;
  for (std::size_t i = 0; i < gradient.size(); ++i) {
    error2 += (v.data[i] - gradient[i]) * (v.data[i] - gradient[i]);
    norm2 += gradient[i] * gradient[i];
  }
  EXPECT_LT(std::sqrt(error2 / norm2), 1e-4);
}

struct LossRun {
  LossValue value;
  Image gradient;
};

LossRun run_with_threads(int threads, const Image& rendered, const Image& target,
                         SsimScratch& scratch) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  tbb::task_arena arena(threads);
  LossRun run;
  arena.execute([&] {
    run.value = photometric_loss(rendered, target, kDefaultSsimWeight, &run.gradient, scratch);
  });
  return run;
}

void expect_identical(const LossRun& a, const LossRun& b, const std::string& what) {
  EXPECT_EQ(a.value.loss, b.value.loss) << what;
  EXPECT_EQ(a.value.l1, b.value.l1) << what;
  EXPECT_EQ(a.value.ssim, b.value.ssim) << what;
  ASSERT_EQ(a.gradient.data.size(), b.gradient.data.size()) << what;
  EXPECT_EQ(std::memcmp(a.gradient.data.data(), b.gradient.data.data(),
                        a.gradient.data.size() * sizeof(float)),
            0)
      << what;
}

TEST(PhotometricLoss, BitIdenticalForAnyThreadCount) {
  constexpr int kW = 200, kH = 150;
  const Image rendered = to_image(random_values(kW, kH, 3, 15), kW, kH, 3);
  const Image target = to_image(random_values(kW, kH, 3, 16), kW, kH, 3);
  SsimScratch fresh_one;
  const LossRun one = run_with_threads(1, rendered, target, fresh_one);
  // Scratch is per-thread inside; one reused while the thread count changes must not matter.
  SsimScratch reused;
  for (const int threads : {2, 4, 1, 2}) {
    SsimScratch fresh;
    expect_identical(run_with_threads(threads, rendered, target, fresh), one,
                     std::to_string(threads) + " threads");
    expect_identical(run_with_threads(threads, rendered, target, reused), one,
                     std::to_string(threads) + " threads, reused scratch");
  }
}

TEST(PhotometricLoss, ScratchReusedAcrossShapesGivesFreshResultsWithoutGrowing) {
  const Image big_a = to_image(random_values(60, 50, 3, 17), 60, 50, 3);
  const Image big_b = to_image(random_values(60, 50, 3, 18), 60, 50, 3);
  const Image a = to_image(random_values(21, 34, 3, 19), 21, 34, 3);
  const Image b = to_image(random_values(21, 34, 3, 20), 21, 34, 3);
  SsimScratch fresh, reused;
  Image v_fresh, v_reused;
  const LossValue expected = photometric_loss(a, b, 0.2f, &v_fresh, fresh);
  photometric_loss(big_a, big_b, 0.2f, &v_reused, reused);
  const float* storage = reused.buffers.data();
  const LossValue value = photometric_loss(a, b, 0.2f, &v_reused, reused);
  EXPECT_EQ(value.loss, expected.loss);
  EXPECT_EQ(v_reused.data, v_fresh.data);
  EXPECT_EQ(reused.buffers.data(), storage);  // the smaller image fit: no new allocation
  photometric_loss(a, b, 0.2f, &v_reused, reused);
  EXPECT_EQ(v_reused.data, v_fresh.data);
}

TEST(PhotometricLoss, RejectsBadShapes) {
  SsimScratch scratch;
  Image v;
  EXPECT_THROW(photometric_loss(Image(8, 6, 3), Image(6, 8, 3), 0.2f, &v, scratch),
               ArgumentError);
  EXPECT_THROW(photometric_loss(Image(8, 6, 3), Image(8, 7, 3), 0.2f, nullptr, scratch),
               ArgumentError);
  EXPECT_THROW(photometric_loss(Image(8, 6, 4), Image(8, 6, 4), 0.2f, &v, scratch),
               ArgumentError);
  EXPECT_THROW(photometric_loss(Image(8, 6, 1), Image(8, 6, 1), 0.2f, &v, scratch),
               ArgumentError);
  EXPECT_THROW(photometric_loss(Image(0, 0, 3), Image(0, 0, 3), 0.2f, &v, scratch),
               ArgumentError);
  Image truncated(8, 6, 3);
  truncated.data.pop_back();
  EXPECT_THROW(photometric_loss(truncated, Image(8, 6, 3), 0.2f, &v, scratch), ArgumentError);
  EXPECT_THROW(ssim(Image(8, 6, 3), Image(8, 6, 4)), ArgumentError);
  EXPECT_THROW(ssim(Image(8, 6, 3), Image(9, 6, 3)), ArgumentError);
  EXPECT_THROW(ssim(Image(), Image()), ArgumentError);
}

}  // namespace
}  // namespace splat
