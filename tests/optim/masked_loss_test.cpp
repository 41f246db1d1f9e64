// The masked training loss (masked_loss.hpp) and masked scoring (metrics.hpp): the gradient
// against central differences, nothing learnt or scored where the mask is 0, and the plain
// loss where it keeps everything.
#include "splat/optim/masked_loss.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "splat/core/error.hpp"
#include "splat/eval/metrics.hpp"

namespace splat {
namespace {

constexpr int kWidth = 13, kHeight = 11;

// Render and photograph 0.05 or more apart everywhere (finite differences of step ≪ 0.05 never
// cross L1's kink), and a mask of zeros, ones and weights between.
struct Case {
  std::vector<double> rendered, target, mask;
};

Case random_case(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.05, 0.95);
  Case c;
  const std::size_t pixels = std::size_t(kWidth) * kHeight;
  for (std::size_t i = 0; i < 3 * pixels; ++i) {
    c.rendered.push_back(u(rng));
    double t = u(rng);
    if (std::abs(t - c.rendered.back()) < 0.05) t = c.rendered.back() + (t < 0.5 ? 0.05 : -0.05);
    c.target.push_back(t);
  }
  for (std::size_t p = 0; p < pixels; ++p) c.mask.push_back(p % 3 == 0 ? 0.0 : p % 3 == 1 ? 1.0 : 0.4 + 0.5 * u(rng));
  return c;
}

double loss(const Case& c, const std::vector<double>& rendered, std::vector<double>* gradient) {
  std::vector<double> masked, buffers;
  if (gradient) gradient->assign(rendered.size(), 0.0);
  return masked_photometric_loss_core<double>(rendered.data(), c.target.data(), c.mask.data(), kWidth, kHeight,
                                              kDefaultSsimWeight, gradient ? gradient->data() : nullptr, masked,
                                              buffers)
      .loss;
}

TEST(MaskedLoss, GradientMatchesCentralDifferencesAndIsZeroWhereMasked) {
  const Case c = random_case(3);
  std::vector<double> gradient;
  loss(c, c.rendered, &gradient);
  constexpr double kStep = 1e-5;
  int kept_nonzero = 0;
  for (std::size_t i = 0; i < c.rendered.size(); ++i) {
    std::vector<double> shifted = c.rendered;
    shifted[i] += kStep;
    const double up = loss(c, shifted, nullptr);
    shifted[i] -= 2 * kStep;
    const double down = loss(c, shifted, nullptr);
    const double numeric = (up - down) / (2 * kStep);
    if (c.mask[i / 3] == 0) {
      EXPECT_EQ(gradient[i], 0.0) << "element " << i;
      EXPECT_EQ(up, down) << "element " << i;  // the loss does not see a masked pixel at all
    } else {
      EXPECT_NEAR(gradient[i], numeric, 1e-4 * std::abs(numeric)) << "element " << i;
      kept_nonzero += gradient[i] != 0;
    }
  }
  EXPECT_GT(kept_nonzero, int(c.rendered.size()) / 2);
}

TEST(MaskedLoss, AMaskOfOnesIsThePlainLoss) {
  const Case c = random_case(4);
  Image rendered(kWidth, kHeight, 3), target(kWidth, kHeight, 3), ones(kWidth, kHeight, 1, 1.0f);
  for (std::size_t i = 0; i < c.rendered.size(); ++i)
    rendered.data[i] = float(c.rendered[i]), target.data[i] = float(c.target[i]);
  Image v_plain, v_masked;
  SsimScratch plain_scratch;
  MaskedLossScratch masked_scratch;
  const LossValue plain = photometric_loss(rendered, target, kDefaultSsimWeight, &v_plain, plain_scratch);
  const LossValue masked = masked_photometric_loss(rendered, target, ones, kDefaultSsimWeight, &v_masked, masked_scratch);
  EXPECT_EQ(plain.loss, masked.loss);
  EXPECT_EQ(v_plain.data, v_masked.data);
  EXPECT_THROW(masked_photometric_loss(rendered, target, Image(kWidth, kHeight, 3), kDefaultSsimWeight, nullptr,
                                       masked_scratch),
               ArgumentError);
}

TEST(MaskedPsnr, ScoresOnlyWhatTheMaskKeeps) {
  Image a(4, 2, 3, 0.5f), b = a, mask(4, 2, 1, 1.0f);
  EXPECT_EQ(masked_psnr(a, b, mask), std::numeric_limits<double>::infinity());
  for (int c = 0; c < 3; ++c) b.at(3, 1, c) = 1.0f;  // one pixel off by 0.5
  EXPECT_NEAR(masked_psnr(a, b, mask), psnr(a, b), 1e-9);
  EXPECT_NEAR(psnr(a, b), -10 * std::log10(0.25 / 8), 1e-9);
  mask.at(3, 1, 0) = 0;  // ...and left out
  EXPECT_EQ(masked_psnr(a, b, mask), std::numeric_limits<double>::infinity());
  mask.at(3, 1, 0) = 1;
  mask.at(0, 0, 0) = mask.at(1, 0, 0) = 0;  // two agreeing pixels left out: the same error over 6
  EXPECT_NEAR(masked_psnr(a, b, mask), -10 * std::log10(0.25 / 6), 1e-9);
  EXPECT_THROW(masked_psnr(a, b, Image(2, 2, 1)), ArgumentError);
}

}  // namespace
}  // namespace splat
