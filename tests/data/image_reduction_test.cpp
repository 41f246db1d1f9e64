// Images read at a reduced size (read_image_reduced) and datasets of photographs beyond the
// pixel limit: a 4200 x 4200 JPEG (17.6 MP, left half red, right half blue) loads at 1/2..1/8
// and loads into a COLMAP dataset with --downscale, is refused whole with advice, and picks a
// downscale of its own.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "splat/core/error.hpp"
#include "splat/data/dataset.hpp"
#include "splat/data/image_io.hpp"
#include "splat/data/resample.hpp"
#include "splat/eval/metrics.hpp"
#include "tests/data/colmap_test_writer.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

fs::path big_jpeg() { return fs::path(SPLAT_TEST_DATA_DIR) / "images" / "big_4200.jpg"; }

void expect_red_left_blue_right(const Image& image) {
  const int y = image.height / 2;
  EXPECT_GT(image.at(image.width / 4, y, 0), 0.9f);
  EXPECT_LT(image.at(image.width / 4, y, 2), 0.1f);
  EXPECT_LT(image.at(3 * image.width / 4, y, 0), 0.1f);
  EXPECT_GT(image.at(3 * image.width / 4, y, 2), 0.9f);
}

TEST(ImageReduction, AJpegBeyondThePixelLimitLoadsReducedAndIsRefusedWhole) {
  EXPECT_THROW(read_image(big_jpeg()), InputError);
  const ImageInfo stored = read_image_stored_size(big_jpeg());
  EXPECT_EQ(stored.width, 4200);
  EXPECT_EQ(stored.height, 4200);
  for (const int reduction : {2, 3, 8, 10}) {
    const Image image = read_image_reduced(big_jpeg(), reduction);
    EXPECT_EQ(image.width, 4200 / reduction) << reduction;
    EXPECT_EQ(image.height, 4200 / reduction) << reduction;
    expect_red_left_blue_right(image);
  }
}

TEST(ImageReduction, IsTheAreaAverageOfTheWholeImage) {
  // A PNG decodes whole: exactly the area average.
  const fs::path dir = test::scratch_dir("image_reduction_png");
  Image noise(40, 30, 3);
  for (std::size_t i = 0; i < noise.data.size(); ++i) noise.data[i] = float((i * 7919) % 256) / 255.0f;
  write_png(noise, dir / "noise.png");
  const Image whole = read_image(dir / "noise.png");
  EXPECT_EQ(read_image_reduced(dir / "noise.png", 4).data, resample_area(whole, 10, 7).data);
  // A JPEG decoded at 1/2 by libjpeg is close to the average of its whole decoding.
  const fs::path small = fs::path(SPLAT_TEST_DATA_DIR) / "images" / "small.jpg";
  const Image reduced = read_image_reduced(small, 2);
  ASSERT_EQ(reduced.width, 16);
  EXPECT_GT(psnr(reduced, resample_area(read_image(small), 16, 16)), 30.0);
  EXPECT_THROW(read_image_reduced(small, 0), ArgumentError);
  EXPECT_THROW(read_image_reduced(small, 33), InputError);  // a side of 0
}

// A COLMAP folder of two views of the big JPEG, one with radial distortion (undistorted at
// the reduced size): image 0 is the test view, 1 trains.
fs::path big_dataset() {
  const fs::path dir = test::scratch_dir("image_reduction_dataset");
  fs::create_directories(dir / "images");
  for (const char* name : {"a.jpg", "b.jpg"})
    fs::copy_file(big_jpeg(), dir / "images" / name, fs::copy_options::overwrite_existing);
  test::TestModel model;
  model.cameras.push_back({1, ColmapCameraModel::kPinhole, 4200, 4200, {3000, 3000, 2100, 2100}});
  model.cameras.push_back({2, ColmapCameraModel::kSimpleRadial, 4200, 4200, {3000, 2100, 2100, 0.01}});
  model.images.push_back({1, {1, 0, 0, 0}, {0, 0, 4}, 1, "a.jpg"});
  model.images.push_back({2, {1, 0, 0, 0}, {0.1, 0, 4}, 2, "b.jpg"});
  model.points.push_back({{0, 0, 0}, {255, 0, 0}});
  test::write_colmap_text(model, dir / "sparse" / "0");
  return dir;
}

TEST(ImageReduction, ADatasetOfPhotosBeyondThePixelLimitTrainsWithADownscale) {
  const fs::path dir = big_dataset();
  DatasetOptions options;
  try {
    load_dataset(dir, options);
    ADD_FAILURE() << "loaded whole";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("beyond the 16777216-pixel limit: train it with --downscale"),
              std::string::npos)
        << e.what();
  }
  options.downscale = 8;
  const Dataset reduced = load_dataset(dir, options);
  ASSERT_EQ(reduced.test.front().image.width, 525);
  EXPECT_EQ(reduced.test.front().camera.width, 525);
  EXPECT_FLOAT_EQ(reduced.test.front().camera.cx, 262.5f);
  expect_red_left_blue_right(reduced.test.front().image);
  EXPECT_LE(reduced.train.front().image.width, 525);  // undistorted, cut to what the lens covers
  EXPECT_GT(reduced.train.front().image.width, 400);
  expect_red_left_blue_right(reduced.train.front().image);
  EXPECT_EQ(reduced.downscale, 8);
  // Images wider than max_width pick the smallest downscale that brings them within it.
  options.downscale = 1;
  options.max_width = 1600;
  const Dataset picked = load_dataset(dir, options);
  EXPECT_EQ(picked.downscale, 3);
  EXPECT_EQ(picked.test.front().image.width, 1400);
  EXPECT_EQ(picked.test.front().image.height, 1400);
}

}  // namespace
}  // namespace splat
