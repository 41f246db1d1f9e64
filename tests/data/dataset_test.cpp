// load_dataset on the benchmark lego400 data, in Blender form and in COLMAP form (skipped when
// ../shared/data is not beside the checkout; the loaders' own tests use folders they write).
#include "splat/data/dataset.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "splat/data/image_io.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

constexpr int kLegoSide = 400;
constexpr std::size_t kLegoTrain = 87, kLegoTest = 13;
// tan(camera_angle_x / 2) for lego: fx = 200 / this.
constexpr double kLegoTanHalfFov = 0.36;

fs::path lego_blender() { return test::benchmark_data_dir() / "lego400"; }
fs::path lego_colmap() { return test::benchmark_data_dir() / "lego400_colmap"; }

std::string three_digits(int i) {
  char text[8];
  std::snprintf(text, sizeof text, "%03d", i);
  return text;
}

void expect_same_camera(const Camera& a, const Camera& b, const std::string& what) {
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r)
      EXPECT_NEAR(a.camera_from_world_rotation[c][r], b.camera_from_world_rotation[c][r], 1e-4)
          << what;
    EXPECT_NEAR(a.camera_from_world_translation[c], b.camera_from_world_translation[c], 1e-4)
        << what;
  }
  EXPECT_NEAR(a.fx, b.fx, 1e-3) << what;  // ~555.56: 1e-4 relative is 0.06
  EXPECT_NEAR(a.fy, b.fy, 1e-3) << what;
  EXPECT_NEAR(a.cx, b.cx, 1e-4) << what;
  EXPECT_NEAR(a.cy, b.cy, 1e-4) << what;
  EXPECT_EQ(a.width, b.width) << what;
  EXPECT_EQ(a.height, b.height) << what;
}

TEST(DatasetLego400, BlenderViewsImagesAndExtent) {
  SPLAT_SKIP_WITHOUT_BENCHMARK_DATA("lego400");
  const Dataset d = load_dataset(lego_blender());
  ASSERT_EQ(d.train.size(), kLegoTrain);
  ASSERT_EQ(d.test.size(), kLegoTest);
  EXPECT_FALSE(d.points.has_value());
  EXPECT_EQ(d.train.front().name, "r_1");
  EXPECT_EQ(d.train.back().name, "r_99");
  for (std::size_t j = 0; j < kLegoTest; ++j) EXPECT_EQ(d.test[j].name, "r_" + std::to_string(8 * j));
  for (const auto* split : {&d.train, &d.test})
    for (const DatasetView& v : *split) {
      ASSERT_EQ(v.image.width, kLegoSide) << v.name;
      ASSERT_EQ(v.image.height, kLegoSide) << v.name;
      ASSERT_EQ(v.image.channels, 3) << v.name;
      ASSERT_EQ(v.image.data.size(), std::size_t(kLegoSide * kLegoSide * 3)) << v.name;
      EXPECT_EQ(v.camera.width, kLegoSide);
      EXPECT_NEAR(v.camera.fx, 200.0 / kLegoTanHalfFov, 1e-2);
      EXPECT_FLOAT_EQ(v.camera.cx, 200.0f);
      // The corners are transparent in the RGBA files: pure background after compositing.
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(v.image.at(0, 0, c), 1.0f) << v.name;
        EXPECT_EQ(v.image.at(kLegoSide - 1, kLegoSide - 1, c), 1.0f) << v.name;
      }
      const auto [lo, hi] = std::minmax_element(v.image.data.begin(), v.image.data.end());
      EXPECT_GE(*lo, 0.0f);
      EXPECT_LE(*hi, 1.0f);
      EXPECT_LT(*lo, 0.2f) << v.name << ": the model should be visible";
    }
  // Lego's cameras sit on a sphere of radius ~4.03 around the model; their mean is near the
  // centre, so 1.1 × the largest distance is a little above 1.1 × 4.03.
  EXPECT_TRUE(std::isfinite(d.scene_extent));
  EXPECT_GT(d.scene_extent, 1.1f * 4.0f);
  EXPECT_LT(d.scene_extent, 1.1f * 4.03f * 1.3f);
  EXPECT_NEAR(d.scene_extent, 5.0878f, 1e-3f);
}

TEST(DatasetLego400, ColmapFormMatchesBlenderForm) {
  SPLAT_SKIP_WITHOUT_BENCHMARK_DATA("lego400");
  SPLAT_SKIP_WITHOUT_BENCHMARK_DATA("lego400_colmap");
  const Dataset blender = load_dataset(lego_blender());
  const Dataset colmap = load_dataset(lego_colmap());
  ASSERT_EQ(colmap.train.size(), kLegoTrain);
  ASSERT_EQ(colmap.test.size(), kLegoTest);
  // Colmap image NNN is lego frame NNN: every 8th in name order is lego's test split.
  for (std::size_t j = 0; j < kLegoTest; ++j) {
    EXPECT_EQ(colmap.test[j].name, three_digits(int(8 * j)));
    expect_same_camera(colmap.test[j].camera, blender.test[j].camera, colmap.test[j].name);
  }
  std::map<std::string, const DatasetView*> blender_train;
  for (const DatasetView& v : blender.train) blender_train[v.name] = &v;
  for (const DatasetView& v : colmap.train) {
    const auto it = blender_train.find("r_" + std::to_string(std::stoi(v.name)));
    ASSERT_NE(it, blender_train.end()) << v.name;
    expect_same_camera(v.camera, it->second->camera, v.name);
  }
  // Both composited onto white; COLMAP's copies were rounded to 8 bits after compositing.
  for (std::size_t j = 0; j < kLegoTest; ++j) {
    const Image& a = colmap.test[j].image;
    const Image& b = blender.test[j].image;
    ASSERT_EQ(a.data.size(), b.data.size());
    float worst = 0;
    for (std::size_t i = 0; i < a.data.size(); ++i)
      worst = std::max(worst, std::abs(a.data[i] - b.data[i]));
    EXPECT_LE(worst, 1.0f / 255 + 1e-5f) << colmap.test[j].name;
  }
  EXPECT_NEAR(colmap.scene_extent, blender.scene_extent, 1e-4f);
  ASSERT_TRUE(colmap.points.has_value());
  EXPECT_EQ(colmap.points->size(), 100000u);
  ASSERT_EQ(colmap.points->colors.size(), 300000u);
  for (float p : colmap.points->positions) ASSERT_LE(std::abs(p), 1.3f + 1e-6f);
  for (float c : colmap.points->colors) ASSERT_TRUE(c >= 0.0f && c <= 1.0f);
}

TEST(DatasetLego400, DownscaleTwoHalvesImagesAndIntrinsics) {
  SPLAT_SKIP_WITHOUT_BENCHMARK_DATA("lego400");
  DatasetOptions options;
  options.downscale = 2;
  const Dataset half = load_dataset(lego_blender(), options);
  ASSERT_EQ(half.train.size(), kLegoTrain);
  ASSERT_EQ(half.test.size(), kLegoTest);
  for (const DatasetView& v : half.test) {
    EXPECT_EQ(v.image.width, kLegoSide / 2);
    EXPECT_EQ(v.image.height, kLegoSide / 2);
    EXPECT_EQ(v.camera.width, kLegoSide / 2);
    EXPECT_NEAR(v.camera.fx, 100.0 / kLegoTanHalfFov, 1e-2);
    EXPECT_FLOAT_EQ(v.camera.cx, 100.0f);
    EXPECT_FLOAT_EQ(v.camera.cy, 100.0f);
  }
  // Each pixel is the mean of its 2 x 2 block of the composited full-size image.
  const Image rgba = read_image(lego_blender() / "test" / "r_8.png");
  const Image& small = half.test[1].image;
  ASSERT_EQ(half.test[1].name, "r_8");
  float worst = 0;
  for (int y = 0; y < small.height; ++y)
    for (int x = 0; x < small.width; ++x)
      for (int c = 0; c < 3; ++c) {
        float sum = 0;
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx) {
            const float a = rgba.at(2 * x + dx, 2 * y + dy, 3);
            sum += rgba.at(2 * x + dx, 2 * y + dy, c) * a + (1 - a);
          }
        worst = std::max(worst, std::abs(small.at(x, y, c) - sum / 4));
      }
  EXPECT_LT(worst, 1e-5f);
  // Training camera centres do not move with the resolution.
  EXPECT_NEAR(half.scene_extent, 5.0878f, 1e-3f);
}

}  // namespace
}  // namespace splat
