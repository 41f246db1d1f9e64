#include "splat/optim/relocation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "splat/core/error.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

TEST(Relocation, OneCopyIsTheGaussianItself) {
  for (float o : {0.01f, 0.3f, 0.9f}) {
    const RelocatedShape shape = relocated_shape(o, 1, 0.005f);
    EXPECT_NEAR(shape.opacity, o, 1e-6f);
    EXPECT_NEAR(shape.scale_ratio, 1.0f, 1e-6f);
  }
}

TEST(Relocation, CopiesTogetherBlockAsMuchLightAtTheCentreAndShrink) {
  for (float o : {0.05f, 0.5f, 0.95f}) {
    float previous_ratio = 1.0f;
    for (int copies : {2, 3, 5, 10}) {
      const RelocatedShape shape = relocated_shape(o, copies, 1e-6f);
      // 1 − (1 − o')^N = o: the stack composites to the original opacity at its centre.
      EXPECT_NEAR(1.0 - std::pow(1.0 - double(shape.opacity), copies), o, 1e-5) << o << " " << copies;
      EXPECT_LT(shape.opacity, o);
      EXPECT_GT(shape.scale_ratio, 0.0f);
      EXPECT_LE(shape.scale_ratio, previous_ratio + 1e-6f) << "more copies never grow the scale";
      previous_ratio = shape.scale_ratio;
    }
  }
  EXPECT_THROW(relocated_shape(0.5f, 0, 0.005f), ArgumentError);
  EXPECT_THROW(relocated_shape(0.5f, kMaxRelocationCopies + 1, 0.005f), ArgumentError);
}

TEST(Relocation, SamplingPicksOnlyEligibleRowsInProportionToOpacity) {
  GaussianModel model = test::random_model(4, 0, 3);
  const float opacities[] = {0.8f, 0.2f, 0.6f, 0.0001f};
  for (int i = 0; i < 4; ++i) model.opacity_logits[i] = logit(opacities[i]);
  const std::vector<std::uint8_t> eligible = {1, 1, 0, 1};  // row 2 is not a source
  std::mt19937 rng(5);
  const std::vector<std::size_t> draws = sample_by_opacity(model, eligible, 20000, rng);
  ASSERT_EQ(draws.size(), 20000u);
  std::vector<int> counts(4, 0);
  for (std::size_t d : draws) ++counts[d];
  EXPECT_EQ(counts[2], 0);
  const double total = 0.8 + 0.2 + 0.0001;
  EXPECT_NEAR(counts[0] / 20000.0, 0.8 / total, 0.015);
  EXPECT_NEAR(counts[1] / 20000.0, 0.2 / total, 0.015);
  EXPECT_LT(counts[3], 20);

  std::mt19937 same(5);
  EXPECT_EQ(sample_by_opacity(model, eligible, 20000, same), draws) << "deterministic for a seed";
  EXPECT_TRUE(sample_by_opacity(model, {0, 0, 0, 0}, 10, rng).empty());
}

// Rows are recognisable by their first mean coordinate; moments are distinct per row.
struct RowsFixture {
  GaussianModel model = test::random_model(6, 1, 11);
  AdamState adam;
  std::vector<float> stat = {10, 11, 12, 13, 14, 15};
  RowsFixture() {
    adam.first_moment = test::random_model(6, 1, 12);
    adam.second_moment = test::random_model(6, 1, 13);
    for (int i = 0; i < 6; ++i) model.opacity_logits[i] = logit(0.5f);
  }
  AlignedRows rows() { return {model, adam, {&stat}}; }
};

TEST(Relocation, RelocatedRowsCopyTheirSourceAndStartWithFreshMoments) {
  RowsFixture f;
  const GaussianModel before = f.model;
  const AdamState adam_before = f.adam;
  AlignedRows rows = f.rows();
  // Rows 1 and 4 are dead; both move onto row 2.
  EXPECT_EQ(relocate_rows(rows, {1, 4}, {2, 2}, 0.005f), 2u);
  ASSERT_EQ(f.model.size(), 6u);
  const RelocatedShape shape = relocated_shape(0.5f, 3, 0.005f);
  for (std::size_t r : {std::size_t(1), std::size_t(2), std::size_t(4)}) {
    EXPECT_EQ(f.model.means[3 * r], before.means[3 * 2]) << r;
    EXPECT_NEAR(sigmoid(f.model.opacity_logits[r]), shape.opacity, 1e-6f);
    EXPECT_NEAR(f.model.log_scales[3 * r], before.log_scales[3 * 2] + std::log(shape.scale_ratio), 1e-5f);
    EXPECT_EQ(f.adam.first_moment.means[3 * r], 0.0f);
    EXPECT_EQ(f.adam.second_moment.sh[r * f.model.sh_coefficients() * 3], 0.0f);
    EXPECT_EQ(f.stat[r], 12.0f);
  }
  for (std::size_t r : {std::size_t(0), std::size_t(3), std::size_t(5)}) {
    EXPECT_EQ(f.model.means[3 * r], before.means[3 * r]);
    EXPECT_EQ(f.adam.first_moment.means[3 * r], adam_before.first_moment.means[3 * r]);
    EXPECT_EQ(f.adam.second_moment.opacity_logits[r], adam_before.second_moment.opacity_logits[r]);
    EXPECT_EQ(f.stat[r], 10.0f + float(r));
  }
  EXPECT_THROW(relocate_rows(rows, {1}, {2, 3}, 0.005f), ArgumentError);
}

TEST(Relocation, AddedCopiesAppendAlignedRows) {
  RowsFixture f;
  const GaussianModel before = f.model;
  AlignedRows rows = f.rows();
  EXPECT_EQ(add_relocated_copies(rows, {0, 5, 0}, 0.005f), 3u);
  ASSERT_EQ(f.model.size(), 9u);
  ASSERT_EQ(f.adam.first_moment.size(), 9u);
  ASSERT_EQ(f.adam.second_moment.size(), 9u);
  ASSERT_EQ(f.stat.size(), 9u);
  const std::size_t sources[] = {0, 5, 0};
  for (std::size_t j = 0; j < 3; ++j) {
    EXPECT_EQ(f.model.means[3 * (6 + j)], before.means[3 * sources[j]]);
    EXPECT_EQ(f.stat[6 + j], f.stat[sources[j]]);
    EXPECT_EQ(f.adam.first_moment.opacity_logits[6 + j], 0.0f);
  }
  // Row 0 was copied twice (three Gaussians in all), row 5 once (two).
  EXPECT_NEAR(sigmoid(f.model.opacity_logits[0]), relocated_shape(0.5f, 3, 0.005f).opacity, 1e-6f);
  EXPECT_NEAR(sigmoid(f.model.opacity_logits[5]), relocated_shape(0.5f, 2, 0.005f).opacity, 1e-6f);
  EXPECT_EQ(f.model.opacity_logits[6], f.model.opacity_logits[0]);
  EXPECT_EQ(f.model.opacity_logits[7], f.model.opacity_logits[5]);
}

}  // namespace
}  // namespace splat
