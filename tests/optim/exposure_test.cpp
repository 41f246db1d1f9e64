// The exposure map (splat/optim/exposure.hpp) against central differences in double, and the
// per-view compensation recovering known maps while holding their mean at the identity.
#include "splat/optim/exposure.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "splat/optim/photometric_loss.hpp"
#include "splat/train/exposure_compensation.hpp"

namespace splat {
namespace {

// L = Σ w·out: its gradient with respect to out is w.
double weighted_output(const std::vector<double>& params, const std::vector<double>& x, const std::vector<double>& w) {
  std::vector<double> out(x.size());
  apply_exposure(params.data(), x.data(), out.data(), x.size() / 3);
  double sum = 0;
  for (std::size_t i = 0; i < out.size(); ++i) sum += w[i] * out[i];
  return sum;
}

TEST(Exposure, VjpMatchesCentralDifferences) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const std::size_t pixels = 37;
  std::vector<double> x(3 * pixels), w(3 * pixels), params(kExposureValues);
  for (double& v : x) v = 0.5 + 0.5 * u(rng);
  for (double& v : w) v = u(rng);
  for (double& v : params) v = 0.3 * u(rng);

  std::vector<double> v_x(x.size()), v_params(kExposureValues);
  apply_exposure_vjp(params.data(), x.data(), w.data(), v_x.data(), v_params.data(), pixels);

  const double h = 1e-6;
  for (int k = 0; k < kExposureValues; ++k) {
    std::vector<double> plus = params, minus = params;
    plus[k] += h;
    minus[k] -= h;
    const double numeric = (weighted_output(plus, x, w) - weighted_output(minus, x, w)) / (2 * h);
    EXPECT_NEAR(v_params[k], numeric, 1e-7 * (1 + std::abs(numeric))) << "parameter " << k;
  }
  for (std::size_t i = 0; i < x.size(); i += 5) {
    std::vector<double> plus = x, minus = x;
    plus[i] += h;
    minus[i] -= h;
    const double numeric = (weighted_output(params, plus, w) - weighted_output(params, minus, w)) / (2 * h);
    EXPECT_NEAR(v_x[i], numeric, 1e-7 * (1 + std::abs(numeric))) << "value " << i;
  }
}

TEST(Exposure, CompensationRecoversKnownMapsAroundTheirMean) {
  // One rendered image; two photographs of it, one brighter and warmer, one darker and cooler
  // by the opposite amounts, so the maps' mean is the identity.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.1, 0.8);
  Image rendered(24, 20, 3);
  for (float& v : rendered.data) v = float(u(rng));
  const double truth[kExposureValues] = {0.15, 0.05, -0.1, 0.03, -0.02, 0.04};
  Image photos[2] = {rendered, rendered};
  for (int view = 0; view < 2; ++view) {
    double params[kExposureValues];
    for (int k = 0; k < kExposureValues; ++k) params[k] = view == 0 ? truth[k] : -truth[k];
    for (std::size_t i = 0; i < rendered.data.size(); ++i) {
      const int c = int(i % 3);
      photos[view].data[i] = float(std::exp(params[c]) * rendered.data[i] + params[3 + c]);
    }
  }

  ExposureCompensation compensation(2);
  Image out, v_image;
  SsimScratch scratch;
  double first_loss = 0, last_loss = 0;
  for (int step = 0; step < 2000; ++step) {
    const int view = step % 2;
    compensation.apply(view, rendered, out);
    const double loss = photometric_loss(out, photos[view], 0.2f, &v_image, scratch).loss;
    if (step < 2) first_loss += loss;
    if (step >= 1998) last_loss += loss;
    compensation.backward_and_step(view, rendered, v_image, 5e-3f * float(std::pow(0.01, step / 2000.0)));
  }
  EXPECT_LT(last_loss, 0.02 * first_loss);
  for (int k = 0; k < kExposureValues; ++k) {
    EXPECT_NEAR(compensation.parameters(0)[k], truth[k], 0.005) << k;
    EXPECT_NEAR(compensation.parameters(0)[k] + compensation.parameters(1)[k], 0.0, 1e-6) << k;
  }
}

}  // namespace
}  // namespace splat
