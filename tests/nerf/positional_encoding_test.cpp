// NeRF positional encoding: hand values, exact ordering, batch form, and its VJP against
// central finite differences in double.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "tests/gradient_check.hpp"
#include "splat/nerf/positional_encoding.hpp"

namespace splat {
namespace {

TEST(NerfEncoding, SizeIsRawPlusSixPerFrequency) {
  EXPECT_EQ(encoded_size(0), 3);
  EXPECT_EQ(encoded_size(4), 27);
  EXPECT_EQ(encoded_size(10), 63);
}

// p = (0.25, 0.5, −1), L = 2: ω₀ = π, ω₁ = 2π, so every value is a known sin/cos.
template <typename Scalar>
void check_hand_values(double tolerance) {
  const Scalar xyz[3] = {Scalar(0.25), Scalar(0.5), Scalar(-1)};
  std::vector<Scalar> out(encoded_size(2), Scalar(-7));
  encode(xyz, 2, out.data());
  const double h = std::numbers::sqrt2 / 2;  // sin(π/4) = cos(π/4)
  const double expected[15] = {
      0.25, 0.5, -1,  // raw x y z
      h,    1,   0,   // sin(π·p)
      h,    0,   -1,  // cos(π·p)
      1,    0,   0,   // sin(2π·p)
      0,    -1,  1,   // cos(2π·p)
  };
  for (int i = 0; i < 15; ++i) EXPECT_NEAR(double(out[i]), expected[i], tolerance) << "entry " << i;
}

TEST(NerfEncoding, HandValuesInDocumentedOrder) {
  check_hand_values<double>(1e-15);
  // float: arguments such as float(π)·0.5 are off by ~1e-7, so values near 0 are too.
  check_hand_values<float>(3e-7);
}

// The double-angle steps between directly evaluated frequencies stay as close to sin and
// cos of the exact 2ᵏπp as the directly evaluated float values are (both within a few units
// in the last place of the largest argument).
TEST(NerfEncoding, DoubledFrequenciesMatchSinAndCos) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> coordinate(-2.0f, 2.0f);
  for (int trial = 0; trial < 200; ++trial) {
    const float xyz[3] = {coordinate(rng), coordinate(rng), coordinate(rng)};
    std::vector<float> out(encoded_size(10));
    std::vector<double> exact(encoded_size(10));
    encode(xyz, 10, out.data());
    const double xyz_exact[3] = {xyz[0], xyz[1], xyz[2]};
    encode(xyz_exact, 10, exact.data());
    for (int k = 0; k < 10; ++k)
      for (int j = 0; j < 6; ++j) {
        const double angle_ulp = std::ldexp(std::numbers::pi * 2.0, k) * 6e-8;  // |2ᵏπp| ≤ 2ᵏ·2π
        EXPECT_NEAR(out[3 + 6 * k + j], exact[3 + 6 * k + j], 4 * angle_ulp + 1e-6) << "k " << k;
      }
  }
}

TEST(NerfEncoding, BatchIsSampleMajorSingleEncodings) {
  const int frequencies = 3, size = encoded_size(frequencies), count = 4;
  const std::vector<double> xyz = test::random_vector(3 * count, 5);
  std::vector<double> batch(size * count);
  encode_batch(xyz.data(), count, frequencies, batch.data());
  std::vector<double> single(size);
  for (int i = 0; i < count; ++i) {
    encode(xyz.data() + 3 * i, frequencies, single.data());
    for (int k = 0; k < size; ++k) EXPECT_EQ(batch[size * i + k], single[k]);
  }
  // Batched VJP = per-sample VJPs.
  const std::vector<double> v = test::random_vector(size * count, 6);
  std::vector<double> v_batch(3 * count, 0.0), v_single(3 * count, 0.0);
  encode_batch_vjp(xyz.data(), count, frequencies, v.data(), v_batch.data());
  for (int i = 0; i < count; ++i)
    encode_vjp(xyz.data() + 3 * i, frequencies, v.data() + size * i, v_single.data() + 3 * i);
  EXPECT_EQ(v_batch, v_single);
}

TEST(NerfEncoding, VjpMatchesFiniteDifferences) {
  for (int frequencies = 0; frequencies <= 6; ++frequencies) {
    const int size = encoded_size(frequencies);
    const std::vector<double> xyz = test::random_vector(3, 100 + frequencies);
    const std::vector<double> v = test::random_vector(size, 200 + frequencies);
    auto f = [&](const std::vector<double>& p) {
      std::vector<double> out(size);
      encode(p.data(), frequencies, out.data());
      return out;
    };
    std::vector<double> analytic(3, 0.0);
    encode_vjp(xyz.data(), frequencies, v.data(), analytic.data());
    // ωₖ up to 32π: the O(h²ω³) central-difference error stays below 1e-7 at h = 1e-6.
    test::expect_vjp_matches(f, xyz, v, analytic, "L = " + std::to_string(frequencies), 1e-6,
                             1e-7);
  }
}

TEST(NerfEncoding, VjpAccumulates) {
  const std::vector<double> xyz = test::random_vector(3, 7);
  const std::vector<double> v = test::random_vector(encoded_size(2), 8);
  std::vector<double> fresh(3, 0.0), accumulated = {1.0, -2.0, 3.0};
  encode_vjp(xyz.data(), 2, v.data(), fresh.data());
  encode_vjp(xyz.data(), 2, v.data(), accumulated.data());
  EXPECT_DOUBLE_EQ(accumulated[0], 1.0 + fresh[0]);
  EXPECT_DOUBLE_EQ(accumulated[1], -2.0 + fresh[1]);
  EXPECT_DOUBLE_EQ(accumulated[2], 3.0 + fresh[2]);
}

}  // namespace
}  // namespace splat
