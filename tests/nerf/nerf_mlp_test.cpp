// The NeRF MLP: parameter layout, initialisation, batched forward against the plain-loop
// reference, backward against central finite differences (double, the same templated code
// as training runs in float), and bit-identical results for 1 and 2 threads.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "tests/gradient_check.hpp"
#include "splat/core/error.hpp"
#include "splat/nerf/nerf_mlp.hpp"
#include "splat/nerf/positional_encoding.hpp"
#include "tests/nerf/nerf_mlp_reference.hpp"

namespace splat {
namespace {

// Small enough to difference every parameter: E_x = 15, E_d = 9, 602 parameters.
NerfMlpConfig small_config(DensityActivation activation = DensityActivation::kSoftplus) {
  NerfMlpConfig c;
  c.position_frequencies = 2;
  c.direction_frequencies = 1;
  c.depth = 3;
  c.width = 8;
  c.skip_layer = 1;
  c.color_width = 6;
  c.density_activation = activation;
  return c;
}

// Instant-NGP's shape in miniature: a hash encoding (a dense level and two hashed ones) in
// front of a one-layer trunk; 2·27 + 2·64·2 table values.
NerfMlpConfig hash_config() {
  NerfMlpConfig c = small_config();
  c.encoding = PositionEncoding::kHash;
  c.hash.levels = 3;
  c.hash.features = 2;
  c.hash.table_log2 = 6;
  c.hash.base_resolution = 2;
  c.hash.max_resolution = 12;
  c.depth = 1;
  c.skip_layer = -1;
  return c;
}

// Positions uniform in [−1.5, 1.5]³, directions unit, [count, 3] each.
template <typename Scalar>
void random_inputs(std::size_t count, unsigned seed, std::vector<Scalar>& positions,
                   std::vector<Scalar>& directions) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.5, 1.5);
  std::normal_distribution<double> normal;
  positions.resize(3 * count);
  directions.resize(3 * count);
  for (std::size_t i = 0; i < count; ++i) {
    double d[3] = {normal(rng), normal(rng), normal(rng)};
    const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; ++k) {
      positions[3 * i + k] = Scalar(uniform(rng));
      directions[3 * i + k] = Scalar(d[k] / length);
    }
  }
}

// Initialised network with every parameter (biases too) nudged, so no bias is zero and the
// gradient of each one is exercised on a generic point (no pre-activation at a ReLU kink).
template <typename Scalar>
BasicNerfMlp<Scalar> perturbed_mlp(const NerfMlpConfig& config, unsigned seed) {
  BasicNerfMlp<Scalar> mlp(config, seed);
  const std::vector<double> noise = test::random_vector(mlp.parameter_count(), seed + 1, 0.2);
  for (std::size_t k = 0; k < noise.size(); ++k) mlp.parameters()[k] += Scalar(noise[k]);
  return mlp;
}

// [sigma (N); rgb (3N)] of a forward pass.
template <typename Scalar>
std::vector<double> outputs(const BasicNerfMlp<Scalar>& mlp, const std::vector<Scalar>& positions,
                            const std::vector<Scalar>& directions) {
  const std::size_t n = positions.size() / 3;
  std::vector<Scalar> sigma(n), rgb(3 * n);
  BasicNerfMlpContext<Scalar> context;
  mlp.forward(positions, directions, sigma, rgb, context);
  std::vector<double> out(sigma.begin(), sigma.end());
  out.insert(out.end(), rgb.begin(), rgb.end());
  return out;
}

TEST(NerfMlp, ParameterCountDefault) {
  const NerfMlp mlp;
  // E_x = 3 + 6·10 = 63, E_d = 3 + 6·4 = 27, W = 256, D = 8, C = 128, one skip:
  //   (E_x + 1)W + (D − 1)(W + 1)W + E_x·W + (W + 1) + (W + 1)W + (W + E_d + 1)C + 3(C + 1)
  const std::size_t ex = 63, ed = 27, w = 256, d = 8, c = 128;
  const std::size_t expected = (ex + 1) * w + (d - 1) * (w + 1) * w + ex * w + (w + 1) +
                               (w + 1) * w + (w + ed + 1) * c + 3 * (c + 1);
  EXPECT_EQ(expected, 595844u);
  EXPECT_EQ(mlp.parameter_count(), expected);
}

TEST(NerfMlp, LayersTileTheParameterVector) {
  for (const NerfMlpConfig& config : {NerfMlpConfig{}, small_config()}) {
    const NerfMlp mlp(config);
    const auto& layers = mlp.layers();
    ASSERT_EQ(layers.size(), std::size_t(config.depth + 4));
    std::size_t offset = 0;
    for (const NerfLayerShape& layer : layers) {
      EXPECT_EQ(layer.offset, offset);
      offset += std::size_t(layer.out) * (layer.in + 1);
    }
    EXPECT_EQ(offset, mlp.parameter_count());
    EXPECT_EQ(layers[config.skip_layer].in,
              config.width + encoded_size(config.position_frequencies));
    EXPECT_EQ(layers[mlp.color_layer()].in,
              config.width + encoded_size(config.direction_frequencies));
  }
  // The small config by hand: 15·8+8, (8+15)·8+8, 8·8+8, 8+1, 8·8+8, (8+9)·6+6, 6·3+3.
  EXPECT_EQ(NerfMlp(small_config()).parameter_count(), 128u + 192 + 72 + 9 + 72 + 108 + 21);
  NerfMlpConfig no_skip = small_config();
  no_skip.skip_layer = -1;
  EXPECT_EQ(NerfMlp(no_skip).parameter_count(), 602u - 15 * 8);
}

TEST(NerfMlp, InitialisationIsGlorotUniformWithZeroBiases) {
  const NerfMlp a(NerfMlpConfig{}, 3), b(NerfMlpConfig{}, 3), c(NerfMlpConfig{}, 4);
  EXPECT_TRUE(std::equal(a.parameters().begin(), a.parameters().end(), b.parameters().begin()));
  EXPECT_FALSE(std::equal(a.parameters().begin(), a.parameters().end(), c.parameters().begin()));
  for (const NerfLayerShape& layer : a.layers()) {
    const float bound = std::sqrt(6.0f / float(layer.in + layer.out));
    const float* w = a.parameters().data() + layer.offset;
    const std::size_t weights = std::size_t(layer.out) * layer.in;
    double sum_squares = 0;
    for (std::size_t k = 0; k < weights; ++k) {
      ASSERT_LE(std::abs(w[k]), bound);
      sum_squares += double(w[k]) * w[k];
    }
    // Uniform on ±bound has variance bound²/3.
    if (weights > 1000) {
      EXPECT_NEAR(sum_squares / double(weights), bound * bound / 3, 0.1 * bound * bound / 3);
    }
    for (int r = 0; r < layer.out; ++r) EXPECT_EQ(w[weights + r], 0.0f);
  }
}

TEST(NerfMlp, RejectsBadConfigsAndShapes) {
  NerfMlpConfig bad = small_config();
  bad.skip_layer = 0;
  EXPECT_THROW(NerfMlp{bad}, ArgumentError);
  bad.skip_layer = 3;  // = depth
  EXPECT_THROW(NerfMlp{bad}, ArgumentError);
  bad = small_config();
  bad.width = 0;
  EXPECT_THROW(NerfMlp{bad}, ArgumentError);

  const NerfMlp mlp(small_config());
  std::vector<float> positions(6), directions(6), sigma(2), rgb(6), short_rgb(5);
  NerfMlpContext context;
  EXPECT_THROW(mlp.forward(positions, directions, sigma, short_rgb, context), ArgumentError);
  mlp.forward(positions, directions, sigma, rgb, context);
  std::vector<float> v_params(mlp.parameter_count()), v_sigma(2), v_rgb(6), v_positions(3);
  EXPECT_THROW(mlp.backward(context, v_sigma, v_rgb, v_params, v_positions), ArgumentError);
  const NerfMlp other(NerfMlpConfig{});
  std::vector<float> other_params(other.parameter_count());
  EXPECT_THROW(other.backward(context, v_sigma, v_rgb, other_params), ArgumentError);
}

// The batched forward (chunks, GEMMs, split concatenations) against plain loops, across
// chunk boundaries (600 samples = 256 + 256 + 88).
template <typename Scalar>
void check_forward_against_reference(const NerfMlpConfig& config, double tolerance) {
  const BasicNerfMlp<Scalar> mlp = perturbed_mlp<Scalar>(config, 11);
  std::vector<Scalar> positions, directions;
  random_inputs<Scalar>(600, 12, positions, directions);
  const std::vector<double> out = outputs(mlp, positions, directions);
  for (std::size_t i = 0; i < 600; ++i) {
    const test::NerfMlpSample<Scalar> expected =
        test::forward_single(mlp, &positions[3 * i], &directions[3 * i]);
    EXPECT_NEAR(out[i], double(expected.sigma), tolerance * (1 + std::abs(double(expected.sigma))))
        << "sigma " << i;
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(out[600 + 3 * i + k], double(expected.rgb[k]), tolerance) << "rgb " << i;
    EXPECT_GE(out[i], 0.0);
  }
}

TEST(NerfMlp, ForwardMatchesPlainLoopReference) {
  NerfMlpConfig medium = small_config(DensityActivation::kRelu);
  medium.width = 40;
  medium.depth = 5;
  medium.skip_layer = 3;
  medium.color_width = 24;
  medium.position_frequencies = 6;
  medium.direction_frequencies = 3;
  check_forward_against_reference<double>(small_config(), 1e-12);
  check_forward_against_reference<double>(medium, 1e-12);
  check_forward_against_reference<float>(medium, 1e-5);
}

// The occupancy grid's density-only queries give exactly forward's σ (the same arithmetic,
// without the colour branch), for a batch spanning several chunks.
TEST(NerfMlp, ForwardDensityEqualsForwardSigmaBitwise) {
  for (const DensityActivation activation : {DensityActivation::kSoftplus, DensityActivation::kRelu}) {
    const NerfMlp mlp = perturbed_mlp<float>(small_config(activation), 31);
    std::vector<float> positions, directions;
    random_inputs<float>(700, 32, positions, directions);
    std::vector<float> sigma(700), rgb(3 * 700), sigma_only(700, -1.0f);
    NerfMlpContext context, density_context;
    mlp.forward(positions, directions, sigma, rgb, context);
    mlp.forward_density(positions, sigma_only, density_context);
    EXPECT_EQ(sigma, sigma_only);
  }
  const NerfMlp mlp(small_config(), 1);
  std::vector<float> three(3), two(2);
  NerfMlpContext context;
  EXPECT_THROW(mlp.forward_density(three, two, context), ArgumentError);
}

// Every parameter's gradient and the position gradient of a 5-sample batch against central
// differences, with random cotangents (and the random-direction dot product test).
void check_gradients(const NerfMlpConfig& config, unsigned seed, std::size_t count = 5) {
  BasicNerfMlp<double> mlp = perturbed_mlp<double>(config, seed);
  std::vector<double> positions, directions;
  random_inputs<double>(count, seed + 2, positions, directions);
  const std::vector<double> v = test::random_vector(4 * count, seed + 3);  // [v_σ; v_rgb]
  const std::vector<double> v_sigma(v.begin(), v.begin() + count);
  const std::vector<double> v_rgb(v.begin() + count, v.end());

  std::vector<double> sigma(count), rgb(3 * count);
  BasicNerfMlpContext<double> context;
  mlp.forward(positions, directions, sigma, rgb, context);
  if (config.density_activation == DensityActivation::kRelu) {
    // Both sides of the density ReLU occur, so both branches of its VJP are checked.
    EXPECT_TRUE(std::any_of(sigma.begin(), sigma.end(), [](double s) { return s > 0; }));
    EXPECT_TRUE(std::any_of(sigma.begin(), sigma.end(), [](double s) { return s == 0; }));
  }
  std::vector<double> v_params(mlp.parameter_count(), 0.0), v_positions(3 * count, 0.0);
  mlp.backward(context, v_sigma, v_rgb, v_params, v_positions);

  const std::vector<double> theta(mlp.parameters().begin(), mlp.parameters().end());
  auto of_parameters = [&](const std::vector<double>& p) {
    std::copy(p.begin(), p.end(), mlp.parameters().begin());
    return outputs(mlp, positions, directions);
  };
  test::expect_vjp_matches(of_parameters, theta, v, v_params, "parameters");
  std::copy(theta.begin(), theta.end(), mlp.parameters().begin());

  auto of_positions = [&](const std::vector<double>& x) { return outputs(mlp, x, directions); };
  test::expect_vjp_matches(of_positions, positions, v, v_positions, "positions");
}

TEST(NerfMlp, GradientsMatchFiniteDifferencesSoftplus) { check_gradients(small_config(), 21); }

TEST(NerfMlp, GradientsMatchFiniteDifferencesReluDensity) {
  check_gradients(small_config(DensityActivation::kRelu), 31, 8);
}

TEST(NerfMlp, GradientsMatchFiniteDifferencesSkipAtLastLayer) {
  NerfMlpConfig config = small_config(DensityActivation::kRelu);
  config.skip_layer = config.depth - 1;
  check_gradients(config, 41, 8);
}

TEST(NerfMlp, GradientsMatchFiniteDifferencesNoSkipDepthOne) {
  NerfMlpConfig config = small_config();
  config.skip_layer = -1;
  check_gradients(config, 51);
  config.depth = 1;
  config.direction_frequencies = 0;
  check_gradients(config, 61);
}

// The tables' gradients too (every entry the 5 samples touch, and the untouched ones zero),
// through the network; and with a skip connection, which feeds the code to a second layer.
TEST(NerfMlp, GradientsMatchFiniteDifferencesHashEncoding) {
  check_gradients(hash_config(), 71);
  NerfMlpConfig deeper = hash_config();
  deeper.depth = 3;
  deeper.skip_layer = 2;
  check_gradients(deeper, 81);
}

TEST(NerfMlp, HashTablesFollowTheLayersInitialisedSmall) {
  const NerfMlp mlp(hash_config(), 3);
  ASSERT_TRUE(mlp.hash_layout().has_value());
  EXPECT_EQ(mlp.parameter_count(), mlp.layer_parameter_count() + mlp.hash_layout()->parameter_count());
  const NerfLayerShape& first = mlp.layers()[0];
  EXPECT_EQ(first.in, 6);  // levels · features
  for (std::size_t k = mlp.layer_parameter_count(); k < mlp.parameter_count(); ++k)
    ASSERT_LE(std::abs(mlp.parameters()[k]), 1e-4f) << k;
}

// A network's settings from a file written before the hash encoding read as the frequency one.
TEST(NerfMlp, SettingsWithoutAnEncodingReadAsFrequency) {
  nlohmann::json j = settings_json(small_config());
  j.erase("encoding");
  j.erase("hash");
  const NerfMlpConfig read = read_nerf_mlp_config(j, {.path = "model.fine", .every_key = true});
  EXPECT_EQ(read, small_config());
  j.erase("width");
  EXPECT_THROW(read_nerf_mlp_config(j, {.path = "model.fine", .every_key = true}), ArgumentError);
}

// Over several chunks and both gradient groups, the float pass (what training runs) agrees
// with the double pass the finite-difference tests check, to float accuracy.
TEST(NerfMlp, FloatGradientsAgreeWithDouble) {
  NerfMlpConfig config = small_config();
  config.width = 32;
  config.color_width = 16;
  const BasicNerfMlp<double> reference = perturbed_mlp<double>(config, 71);
  NerfMlp mlp(config);
  std::copy(reference.parameters().begin(), reference.parameters().end(), mlp.parameters().begin());
  const std::size_t n = 2500;  // 10 chunks: two groups of partial gradients
  std::vector<double> positions, directions;
  random_inputs<double>(n, 72, positions, directions);
  const std::vector<double> v = test::random_vector(4 * n, 73);
  const std::vector<float> positions_f(positions.begin(), positions.end()),
      directions_f(directions.begin(), directions.end()), v_f(v.begin(), v.end());

  std::vector<double> sigma(n), rgb(3 * n), g(reference.parameter_count(), 0.0), gx(3 * n, 0.0);
  BasicNerfMlpContext<double> context;
  reference.forward(positions, directions, sigma, rgb, context);
  reference.backward(context, std::span(v).first(n), std::span(v).subspan(n), g, gx);

  std::vector<float> sigma_f(n), rgb_f(3 * n), g_f(mlp.parameter_count(), 0.0f), gx_f(3 * n, 0.0f);
  NerfMlpContext context_f;
  mlp.forward(positions_f, directions_f, sigma_f, rgb_f, context_f);
  mlp.backward(context_f, std::span(v_f).first(n), std::span(v_f).subspan(n), g_f, gx_f);

  // Sums over 2,500 samples: compare against the largest gradient, not entry by entry.
  const double scale = std::abs(*std::max_element(g.begin(), g.end(), [](double a, double b) {
    return std::abs(a) < std::abs(b);
  }));
  for (std::size_t k = 0; k < g.size(); ++k) EXPECT_NEAR(g_f[k], g[k], 1e-4 * scale) << k;
  for (std::size_t k = 0; k < gx.size(); ++k)
    EXPECT_NEAR(gx_f[k], gx[k], 1e-4 * (1 + std::abs(gx[k]))) << k;
}

TEST(NerfMlp, BackwardAddsIntoGradients) {
  const NerfMlp mlp = perturbed_mlp<float>(small_config(), 81);
  std::vector<float> positions, directions;
  random_inputs<float>(100, 82, positions, directions);  // one chunk: g + g is exact
  std::vector<float> sigma(100), rgb(300), v_sigma(100, 0.5f), v_rgb(300, -0.25f);
  NerfMlpContext context;
  mlp.forward(positions, directions, sigma, rgb, context);
  std::vector<float> once(mlp.parameter_count(), 0.0f), twice(mlp.parameter_count(), 0.0f);
  mlp.backward(context, v_sigma, v_rgb, once);
  mlp.backward(context, v_sigma, v_rgb, twice);
  mlp.backward(context, v_sigma, v_rgb, twice);
  for (std::size_t k = 0; k < once.size(); ++k) ASSERT_EQ(twice[k], 2 * once[k]) << k;
}

TEST(NerfMlp, ContextIsReusedAcrossBatchSizes) {
  const NerfMlp mlp = perturbed_mlp<float>(small_config(), 91);
  std::vector<float> big_p, big_d, p, d;
  random_inputs<float>(600, 92, big_p, big_d);
  random_inputs<float>(7, 93, p, d);
  NerfMlpContext reused;
  std::vector<float> big_sigma(600), big_rgb(1800);
  mlp.forward(big_p, big_d, big_sigma, big_rgb, reused);
  const std::size_t capacity = reused.capacity;
  const float* storage = reused.trunk.data();

  std::vector<float> sigma(7), rgb(21), fresh_sigma(7), fresh_rgb(21);
  mlp.forward(p, d, sigma, rgb, reused);
  EXPECT_EQ(reused.capacity, capacity);
  EXPECT_EQ(reused.trunk.data(), storage);  // no reallocation for a smaller batch
  NerfMlpContext fresh;
  mlp.forward(p, d, fresh_sigma, fresh_rgb, fresh);
  EXPECT_EQ(sigma, fresh_sigma);
  EXPECT_EQ(rgb, fresh_rgb);

  std::vector<float> v_sigma(7, 1.0f), v_rgb(21, 1.0f);
  std::vector<float> g(mlp.parameter_count(), 0.0f), g_fresh(mlp.parameter_count(), 0.0f);
  mlp.backward(reused, v_sigma, v_rgb, g);
  mlp.backward(fresh, v_sigma, v_rgb, g_fresh);
  EXPECT_EQ(g, g_fresh);
}

// The default network on 3,000 samples (12 chunks, two gradient groups): forward outputs,
// parameter and position gradients are the same bytes with 1 and with 2 threads.
class NerfMlpThreads : public ::testing::TestWithParam<PositionEncoding> {};

TEST_P(NerfMlpThreads, ThreadCountInvariantBitwise) {
  NerfMlpConfig config;
  config.encoding = GetParam();
  const NerfMlp mlp(config, 5);
  const std::size_t n = 3000;
  std::vector<float> positions, directions;
  random_inputs<float>(n, 101, positions, directions);
  std::vector<float> v_sigma(n), v_rgb(3 * n);
  const std::vector<double> v = test::random_vector(4 * n, 102);
  std::copy(v.begin(), v.begin() + n, v_sigma.begin());
  std::copy(v.begin() + n, v.end(), v_rgb.begin());

  struct Result {
    std::vector<float> sigma, rgb, v_params, v_positions;
  };
  const auto run = [&](int threads) {
    Result r{std::vector<float>(n), std::vector<float>(3 * n),
             std::vector<float>(mlp.parameter_count(), 0.0f), std::vector<float>(3 * n, 0.0f)};
    tbb::task_arena arena(threads);
    arena.execute([&] {
      NerfMlpContext context;
      mlp.forward(positions, directions, r.sigma, r.rgb, context);
      mlp.backward(context, v_sigma, v_rgb, r.v_params, r.v_positions);
    });
    return r;
  };
  // A second single-thread run too: its fresh context sits elsewhere in memory, which
  // alignment-dependent kernels (Eigen's rowwise().sum()) once turned into different bits.
  const Result one = run(1), two = run(2), again = run(1);
  const auto same_bytes = [](const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
  };
  EXPECT_TRUE(same_bytes(one.sigma, two.sigma));
  EXPECT_TRUE(same_bytes(one.rgb, two.rgb));
  EXPECT_TRUE(same_bytes(one.v_params, two.v_params));
  EXPECT_TRUE(same_bytes(one.v_positions, two.v_positions));
  EXPECT_TRUE(same_bytes(one.v_params, again.v_params));
  EXPECT_TRUE(
      std::any_of(one.v_params.begin(), one.v_params.end(), [](float g) { return g != 0; }));
}

INSTANTIATE_TEST_SUITE_P(Encodings, NerfMlpThreads,
                         ::testing::Values(PositionEncoding::kFrequency, PositionEncoding::kHash));

}  // namespace
}  // namespace splat
