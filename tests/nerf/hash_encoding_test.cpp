// The multiresolution hash encoding: its levels' layout, interpolation that reproduces what
// trilinear interpolation must, and both VJPs (tables and positions) against central
// finite differences in double (the same templated code training runs in float).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "splat/core/error.hpp"
#include "splat/nerf/hash_encoding.hpp"
#include "tests/gradient_check.hpp"

namespace splat {
namespace {

// Three levels: R = 2 (27 vertices, dense), then 4 and 12 (hashed into 64 entries).
HashEncodingSettings small_settings() {
  HashEncodingSettings s;
  s.levels = 3;
  s.features = 2;
  s.table_log2 = 6;
  s.base_resolution = 2;
  s.max_resolution = 12;
  return s;
}

std::vector<double> random_unit_points(std::size_t count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(0.02, 0.98);
  std::vector<double> u(3 * count);
  for (double& x : u) x = uniform(rng);
  return u;
}

std::vector<double> encode(const HashGridLayout& layout, const std::vector<double>& table,
                           const std::vector<double>& points) {
  const std::size_t n = points.size() / 3;
  std::vector<double> out(n * std::size_t(layout.output_size()));
  hash_encode(layout, table.data(), points.data(), n, out.data());
  return out;
}

TEST(HashEncoding, LevelsRunFromTheBaseToTheMaxResolutionAndTileTheTable) {
  const HashGridLayout layout(small_settings());
  ASSERT_EQ(layout.levels().size(), 3u);
  EXPECT_EQ(layout.levels()[0].resolution, 2);
  EXPECT_EQ(layout.levels()[1].resolution, 4);  // ⌊2·√6⌋
  EXPECT_EQ(layout.levels()[2].resolution, 12);
  EXPECT_TRUE(layout.levels()[0].dense);
  EXPECT_EQ(layout.levels()[0].entries, 27u);
  EXPECT_FALSE(layout.levels()[1].dense);  // 125 vertices > 64
  EXPECT_EQ(layout.levels()[1].entries, 64u);
  std::size_t offset = 0;
  for (const auto& level : layout.levels()) {
    EXPECT_EQ(level.offset, offset);
    offset += level.entries * 2;
  }
  EXPECT_EQ(layout.parameter_count(), offset);
  EXPECT_EQ(layout.output_size(), 6);

  // The defaults: 16 levels from 16 to 1,024 cells, the first dense, the finest hashed.
  const HashGridLayout defaults{HashEncodingSettings{}};
  EXPECT_EQ(defaults.levels().front().resolution, 16);
  EXPECT_EQ(defaults.levels().back().resolution, 1024);
  EXPECT_TRUE(defaults.levels().front().dense);
  EXPECT_FALSE(defaults.levels().back().dense);
  for (std::size_t l = 1; l < defaults.levels().size(); ++l)
    EXPECT_GT(defaults.levels()[l].resolution, defaults.levels()[l - 1].resolution);
}

TEST(HashEncoding, RejectsBadSettings) {
  HashEncodingSettings s = small_settings();
  s.max_resolution = 1;
  EXPECT_THROW(HashGridLayout{s}, ArgumentError);
  s = small_settings();
  s.levels = 0;
  EXPECT_THROW(HashGridLayout{s}, ArgumentError);
  s = small_settings();
  s.levels = 32;
  s.features = 8;
  s.table_log2 = 22;  // 2^30 values
  EXPECT_THROW(HashGridLayout{s}, ArgumentError);
}

// On a dense level, a table that is an affine function of the vertex coordinates
// interpolates to the same function of u·R everywhere (trilinear interpolation is exact on
// affine functions), and a vertex reads its own entry.
TEST(HashEncoding, DenseLevelInterpolatesAffineTablesExactly) {
  HashEncodingSettings s;
  s.levels = 1;
  s.features = 1;
  s.table_log2 = 10;
  s.base_resolution = s.max_resolution = 4;  // 125 vertices, dense
  const HashGridLayout layout(s);
  ASSERT_TRUE(layout.levels()[0].dense);
  std::vector<double> table(layout.parameter_count());
  for (int z = 0; z <= 4; ++z)
    for (int y = 0; y <= 4; ++y)
      for (int x = 0; x <= 4; ++x) table[std::size_t(x + 5 * (y + 5 * z))] = 0.5 + 1.0 * x - 2.0 * y + 0.25 * z;
  const std::vector<double> points = random_unit_points(50, 3);
  const std::vector<double> code = encode(layout, table, points);
  for (std::size_t i = 0; i < 50; ++i) {
    const double* u = &points[3 * i];
    EXPECT_NEAR(code[i], 0.5 + 4 * u[0] - 8 * u[1] + 1.0 * u[2], 1e-12) << i;
  }
  const std::vector<double> corner = {0.25, 0.5, 1.0};  // vertex (1, 2, 4)
  EXPECT_DOUBLE_EQ(encode(layout, table, corner)[0], table[1 + 5 * (2 + 5 * 4)]);
}

TEST(HashEncoding, PointsOutsideTheCubeAreClamped) {
  const HashGridLayout layout(small_settings());
  const std::vector<double> table = test::random_vector(layout.parameter_count(), 5);
  EXPECT_EQ(encode(layout, table, {-0.5, 1.7, 0.3}), encode(layout, table, {0.0, 1.0, 0.3}));
}

TEST(HashEncoding, TableGradientMatchesFiniteDifferences) {
  const HashGridLayout layout(small_settings());
  const std::size_t n = 6;
  const std::vector<double> points = random_unit_points(n, 7);
  const std::vector<double> table = test::random_vector(layout.parameter_count(), 8);
  const std::vector<double> v = test::random_vector(n * 6, 9);
  std::vector<double> v_table(layout.parameter_count(), 0.0);
  for (int level = 0; level < 3; ++level)
    hash_encode_vjp_table(layout, level, points.data(), n, v.data(), v_table.data());
  test::expect_vjp_matches([&](const std::vector<double>& t) { return encode(layout, t, points); }, table, v,
                           v_table, "table");
}

TEST(HashEncoding, PositionGradientMatchesFiniteDifferences) {
  const HashGridLayout layout(small_settings());
  const std::size_t n = 6;
  const std::vector<double> points = random_unit_points(n, 11);
  const std::vector<double> table = test::random_vector(layout.parameter_count(), 12);
  const std::vector<double> v = test::random_vector(n * 6, 13);
  std::vector<double> v_points(3 * n, 0.0);
  hash_encode_vjp_positions(layout, table.data(), points.data(), n, v.data(), v_points.data());
  test::expect_vjp_matches([&](const std::vector<double>& u) { return encode(layout, table, u); }, points, v,
                           v_points, "positions", 1e-6, 1e-7);
}

}  // namespace
}  // namespace splat
