#include "splat/gaussians/gaussian_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <set>
#include <vector>

#include "splat/core/error.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

// Every float of row `row`, in a fixed order, for comparing rows across models.
std::vector<float> row_values(const GaussianModel& m, std::size_t row) {
  std::vector<float> out;
  auto take = [&](const std::vector<float>& array, std::size_t width) {
    for (std::size_t j = 0; j < width; ++j) out.push_back(array[row * width + j]);
  };
  take(m.means, 3);
  take(m.log_scales, 3);
  take(m.quats, 4);
  take(m.opacity_logits, 1);
  take(m.sh, std::size_t(m.sh_coefficients()) * 3);
  return out;
}

TEST(GaussianModelParameters, AccessorsApplyTheActivations) {
  const GaussianModel m = test::random_model(5, 1, 3);
  for (std::size_t i = 0; i < m.size(); ++i) {
    EXPECT_EQ(m.opacity(i), 1.0f / (1.0f + std::exp(-m.opacity_logits[i])));
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(m.mean(i)[a], m.means[3 * i + a]);
      EXPECT_EQ(m.scale(i)[a], std::exp(m.log_scales[3 * i + a]));
    }
    for (int k = 0; k < 4; ++k) EXPECT_EQ(m.quat(i)[k], m.quats[4 * i + k]);
    // The rotation is the normalised quaternion's: orthonormal whatever the stored length.
    const Mat3<float> r = m.rotation(i);
    const Mat3<float> should_be_identity = glm::transpose(r) * r;
    for (int c = 0; c < 3; ++c)
      for (int row = 0; row < 3; ++row) EXPECT_NEAR(should_be_identity[c][row], c == row ? 1.0f : 0.0f, 1e-5f);
  }
}

TEST(GaussianModelParameters, TheGroupsListEveryArrayOnceWithItsWidth) {
  GaussianModel m = test::random_model(4, 2, 9);
  std::set<const std::vector<float>*> arrays;
  std::size_t floats = 0;
  for (const ParameterGroup& group : kParameterGroups) {
    EXPECT_EQ(group.of(m).size(), m.size() * group.width(m.sh_degree)) << group.name;
    EXPECT_EQ(&parameter_group(group.id), &group);
    arrays.insert(&group.of(m));
    floats += group.width(m.sh_degree);
  }
  EXPECT_EQ(arrays.size(), 5u);
  EXPECT_EQ(floats, m.floats_per_row());
  // The SH degree (padded to the vectors' alignment) and these five arrays are the whole model:
  // an array added to GaussianModel belongs in kParameterGroups too.
  EXPECT_EQ(sizeof(GaussianModel), alignof(std::vector<float>) + 5 * sizeof(std::vector<float>));
}

TEST(GaussianModelRows, FloatsPerRowIs59AtDegree3) {
  GaussianModel m;
  m.sh_degree = 3;
  EXPECT_EQ(m.floats_per_row(), 59u);
  m.resize(2);
  EXPECT_EQ(row_values(m, 1).size(), 59u);
}

TEST(GaussianModelRows, KeepRowsPreservesOrderOfKeptRows) {
  const GaussianModel original = test::random_model(7, 2, 11);
  GaussianModel m = original;
  const std::vector<std::uint8_t> keep = {1, 0, 0, 1, 1, 0, 1};
  m.keep_rows(keep);
  ASSERT_EQ(m.size(), 4u);
  EXPECT_NO_THROW(m.check_consistent());
  const std::size_t kept[] = {0, 3, 4, 6};
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(row_values(m, i), row_values(original, kept[i]));
}

TEST(GaussianModelRows, KeepRowsRejectsWrongFlagCount) {
  GaussianModel m = test::random_model(3, 0, 1);
  EXPECT_THROW(m.keep_rows({1, 0}), ArgumentError);
}

TEST(GaussianModelRows, KeepNoneAndKeepAll) {
  const GaussianModel original = test::random_model(5, 1, 2);
  GaussianModel all = original;
  all.keep_rows(std::vector<std::uint8_t>(5, 1));
  for (std::size_t i = 0; i < 5; ++i) EXPECT_EQ(row_values(all, i), row_values(original, i));
  GaussianModel none = original;
  none.keep_rows(std::vector<std::uint8_t>(5, 0));
  EXPECT_EQ(none.size(), 0u);
  EXPECT_NO_THROW(none.check_consistent());
}

TEST(GaussianModelRows, AppendRowsConcatenates) {
  const GaussianModel a = test::random_model(3, 3, 5), b = test::random_model(2, 3, 6);
  GaussianModel m = a;
  m.append_rows(b);
  ASSERT_EQ(m.size(), 5u);
  EXPECT_NO_THROW(m.check_consistent());
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(row_values(m, i), row_values(a, i));
  for (std::size_t i = 0; i < 2; ++i) EXPECT_EQ(row_values(m, 3 + i), row_values(b, i));
}

TEST(GaussianModelRows, AppendRowsRejectsOtherDegree) {
  GaussianModel m = test::random_model(3, 3, 5);
  EXPECT_THROW(m.append_rows(test::random_model(1, 2, 6)), ArgumentError);
  EXPECT_EQ(m.size(), 3u);
}

TEST(GaussianModelRows, AppendZeroRowsAddsZeros) {
  const GaussianModel a = test::random_model(2, 1, 8);
  GaussianModel m = a;
  m.append_zero_rows(3);
  ASSERT_EQ(m.size(), 5u);
  EXPECT_NO_THROW(m.check_consistent());
  EXPECT_EQ(row_values(m, 1), row_values(a, 1));
  for (std::size_t i = 2; i < 5; ++i)
    for (float x : row_values(m, i)) EXPECT_EQ(x, 0.0f);
}

TEST(GaussianModelRows, GatherRowsFollowsTheListWithRepeats) {
  const GaussianModel a = test::random_model(4, 2, 9);
  const GaussianModel g = a.gather_rows({3, 1, 3});
  ASSERT_EQ(g.size(), 3u);
  EXPECT_EQ(g.sh_degree, 2);
  EXPECT_EQ(row_values(g, 0), row_values(a, 3));
  EXPECT_EQ(row_values(g, 1), row_values(a, 1));
  EXPECT_EQ(row_values(g, 2), row_values(a, 3));
  EXPECT_THROW(a.gather_rows({4}), ArgumentError);
}

TEST(GaussianModelRows, CopyRowAndSetZero) {
  const GaussianModel a = test::random_model(3, 1, 12);
  GaussianModel m = test::random_model(2, 1, 13);
  const std::vector<float> untouched = row_values(m, 1);
  m.copy_row(0, a, 2);
  EXPECT_EQ(row_values(m, 0), row_values(a, 2));
  EXPECT_EQ(row_values(m, 1), untouched);
  EXPECT_THROW(m.copy_row(2, a, 0), ArgumentError);
  EXPECT_THROW(m.copy_row(0, test::random_model(1, 0, 1), 0), ArgumentError);
  m.set_zero();
  EXPECT_EQ(m.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i)
    for (float x : row_values(m, i)) EXPECT_EQ(x, 0.0f);
}

}  // namespace
}  // namespace splat
