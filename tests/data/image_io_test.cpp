#include "splat/data/image_io.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "splat/core/error.hpp"
#include "tests/cli_support.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

// A gradient over every channel, with values spread across [0, 1] so quantisation is tested
// away from the end points too.
Image gradient_image(int width, int height, int channels) {
  Image image(width, height, channels);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < channels; ++c)
        image.at(x, y, c) = float((x * 7 + y * 13 + c * 29) % 101) / 100.0f;
  return image;
}

// Names of files in `dir` other than `keep`: leftovers of a failed atomic write.
std::vector<std::string> other_files(const fs::path& dir, const std::string& keep = "") {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().filename() != keep) names.push_back(entry.path().filename().string());
  return names;
}

template <class F>
std::string input_error_message(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError thrown";
  return "";
}

void expect_round_trip(int channels, int bits) {
  const fs::path dir = test::scratch_dir("image_io_round_trip_" + std::to_string(channels) +
                                         "_" + std::to_string(bits));
  const fs::path file = dir / "image.png";
  const Image original = gradient_image(37, 23, channels);
  write_png(original, file, bits);
  const Image back = read_image(file);
  ASSERT_EQ(back.width, original.width);
  ASSERT_EQ(back.height, original.height);
  ASSERT_EQ(back.channels, channels);
  // Rounding to the nearest code is off by at most half a code.
  const float tolerance = 0.5f / float((1 << bits) - 1) + 1e-6f;
  for (std::size_t i = 0; i < original.data.size(); ++i)
    ASSERT_NEAR(back.data[i], original.data[i], tolerance) << "value " << i;
  EXPECT_EQ(other_files(dir, "image.png").size(), 0u) << "temporary left behind";
}

TEST(ImageIo, Png8BitRoundTripRgb) { expect_round_trip(3, 8); }
TEST(ImageIo, Png8BitRoundTripRgba) { expect_round_trip(4, 8); }
TEST(ImageIo, Png16BitRoundTripRgb) { expect_round_trip(3, 16); }
TEST(ImageIo, Png16BitRoundTripRgba) { expect_round_trip(4, 16); }
TEST(ImageIo, Png8BitRoundTripGray) { expect_round_trip(1, 8); }

TEST(ImageIo, PngKeepsStraightAlpha) {
  // Colour under transparent or half-transparent alpha must come back as written, not
  // premultiplied (datasets composite RGBA onto the background themselves).
  const fs::path file = test::scratch_dir("image_io_alpha") / "alpha.png";
  Image image(2, 1, 4);
  const float pixels[2][4] = {{0.8f, 0.4f, 0.2f, 0.0f}, {0.8f, 0.4f, 0.2f, 0.5f}};
  for (int x = 0; x < 2; ++x)
    for (int c = 0; c < 4; ++c) image.at(x, 0, c) = pixels[x][c];
  write_png(image, file, 16);
  const Image back = read_image(file);
  for (int x = 0; x < 2; ++x)
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(back.at(x, 0, c), pixels[x][c], 1e-4f) << x << c;
}

TEST(ImageIo, PngClampsOutOfRangeValues) {
  const fs::path file = test::scratch_dir("image_io_clamp") / "clamp.png";
  Image image(4, 1, 1);
  image.data = {-0.5f, 1.7f, std::numeric_limits<float>::infinity(),
                std::numeric_limits<float>::quiet_NaN()};
  for (int bits : {8, 16}) {
    write_png(image, file, bits);
    const Image back = read_image(file);
    ASSERT_EQ(back.data.size(), 4u);
    EXPECT_EQ(back.data[0], 0.0f) << bits;
    EXPECT_EQ(back.data[1], 1.0f) << bits;
    EXPECT_EQ(back.data[2], 1.0f) << bits;
    EXPECT_EQ(back.data[3], 0.0f) << "NaN becomes 0, bits " << bits;
  }
}

TEST(ImageIo, PngRejectsBadBitDepthAndChannelCount) {
  const fs::path dir = test::scratch_dir("image_io_bad_args");
  EXPECT_THROW(write_png(Image(2, 2, 3), dir / "a.png", 12), ArgumentError);
  EXPECT_THROW(write_png(Image(2, 2, 5), dir / "b.png"), ArgumentError);
  EXPECT_THROW(write_png(Image(), dir / "c.png"), ArgumentError);
  EXPECT_TRUE(other_files(dir).empty());
}

TEST(ImageIo, ReadMissingFileNamesIt) {
  const fs::path file = test::scratch_dir("image_io_missing") / "no_such_image.png";
  EXPECT_NE(input_error_message([&] { read_image(file); }).find("no_such_image.png"),
            std::string::npos);
  EXPECT_NE(input_error_message([&] { read_image_info(file); }).find("no_such_image.png"),
            std::string::npos);
}

TEST(ImageIo, ReadNonImageNamesItAndPrintsNothing) {
  const fs::path dir = test::scratch_dir("image_io_not_image");
  test::write_text(dir / "notes.png", "this is text, not a PNG\n");
  test::write_text(dir / "notes.txt", "plain text\n");
  testing::internal::CaptureStderr();
  const std::string png_message = input_error_message([&] { read_image(dir / "notes.png"); });
  const std::string txt_message = input_error_message([&] { read_image(dir / "notes.txt"); });
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  EXPECT_NE(png_message.find("notes.png"), std::string::npos) << png_message;
  EXPECT_NE(txt_message.find("notes.txt"), std::string::npos) << txt_message;
}

// libjpeg fills a truncated JPEG with grey and only leaves a message: that image is not the
// photograph, so it is an error (one line, naming the file), as a damaged header is.
TEST(ImageIo, DamagedJpegIsAnErrorNotAGreyPaddedImage) {
  const fs::path original = fs::path(SPLAT_TEST_DATA_DIR) / "images" / "small.jpg";
  const Image intact = read_image(original);
  EXPECT_EQ(intact.width, 32);
  EXPECT_EQ(intact.channels, 3);
  const std::string bytes = test::read_file(original);
  const fs::path dir = test::scratch_dir("image_io_damaged_jpeg");
  std::string corrupt = bytes;
  for (std::size_t i = 2; i < 66; ++i) corrupt[i] = char(corrupt[i] ^ 0x55);  // the headers after SOI
  const std::vector<std::pair<std::string, std::string>> damaged = {
      {"truncated.jpg", bytes.substr(0, bytes.size() * 3 / 4)}, {"corrupt.jpg", corrupt}};
  for (const auto& [name, content] : damaged) {
    const fs::path file = dir / name;
    test::write_text(file, content);
    testing::internal::CaptureStderr();
    const std::string message = input_error_message([&] { read_image(file); });
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
    EXPECT_EQ(message.rfind(file.string() + ": ", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

TEST(ImageIo, ErrorsDoNotLeakIntoLaterCalls) {
  const fs::path dir = test::scratch_dir("image_io_no_leak");
  const std::string first = input_error_message([&] { read_image(dir / "first_missing.png"); });
  const std::string second = input_error_message([&] { read_image(dir / "second_missing.png"); });
  EXPECT_EQ(second.find("first_missing"), std::string::npos) << second;
  // A success after a failure is unaffected, and the next failure reports only itself.
  write_png(Image(3, 2, 3, 0.5f), dir / "fine.png");
  EXPECT_EQ(read_image(dir / "fine.png").width, 3);
  const std::string third = input_error_message([&] { read_image(dir / "third_missing.png"); });
  EXPECT_EQ(third.find("second_missing"), std::string::npos) << third;
  EXPECT_NE(third.find("third_missing"), std::string::npos) << third;
}

TEST(ImageIo, WriteIntoMissingFolderThrowsAndLeavesNothing) {
  const fs::path dir = test::scratch_dir("image_io_missing_folder");
  const fs::path file = dir / "absent" / "out.png";
  const std::string message = input_error_message([&] { write_png(Image(4, 4, 3), file); });
  EXPECT_NE(message.find("out.png"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(dir / "absent"));
  EXPECT_TRUE(other_files(dir).empty());
  EXPECT_NE(input_error_message([&] { write_float_image(Image(4, 4, 3), dir / "absent" / "f.exr"); })
                .find("f.exr"),
            std::string::npos);
  EXPECT_TRUE(other_files(dir).empty());
}

TEST(ImageIo, FailedWriteKeepsThePreviousFile) {
  const fs::path dir = test::scratch_dir("image_io_keep_previous");
  const fs::path file = dir / "out.exr";
  write_float_image(Image(2, 2, 1, 0.25f), file);
  // A format that cannot store floats fails before anything replaces the target.
  EXPECT_THROW(write_float_image(Image(2, 2, 1, 7.0f), dir / "out.png"), InputError);
  EXPECT_TRUE(other_files(dir, "out.exr").empty());
  EXPECT_EQ(read_image(file).data[0], 0.25f);
}

TEST(ImageIo, FloatExrRoundTripIsExact) {
  const fs::path dir = test::scratch_dir("image_io_exr");
  const fs::path file = dir / "values.exr";
  Image image = gradient_image(19, 11, 4);
  // Values no integer format could hold: negative, above 1, tiny, huge.
  image.data[0] = -3.25f;
  image.data[1] = 1234.5f;
  image.data[2] = 1e-20f;
  image.data[3] = 0.1f;
  write_float_image(image, file);
  const Image back = read_image(file);
  ASSERT_EQ(back.width, image.width);
  ASSERT_EQ(back.height, image.height);
  ASSERT_EQ(back.channels, image.channels);
  EXPECT_EQ(back.data, image.data);
  EXPECT_EQ(other_files(dir, "values.exr").size(), 0u);
}

TEST(ImageIo, ReadsLegoTrainingImageAsRgba400) {
  SPLAT_SKIP_WITHOUT_BENCHMARK_DATA("lego400");
  const fs::path folder = test::benchmark_data_dir() / "lego400" / "train";
  ASSERT_TRUE(fs::is_directory(folder)) << folder;
  fs::path file;
  for (const auto& entry : fs::directory_iterator(folder))
    if (entry.path().extension() == ".png") file = entry.path();
  ASSERT_FALSE(file.empty()) << "no PNG in " << folder;
  const ImageInfo info = read_image_info(file);
  EXPECT_EQ(info.width, 400);
  EXPECT_EQ(info.height, 400);
  EXPECT_EQ(info.channels, 4);
  const Image image = read_image(file);
  ASSERT_EQ(image.width, 400);
  ASSERT_EQ(image.height, 400);
  ASSERT_EQ(image.channels, 4);
  float min_alpha = 1, max_alpha = 0;
  for (std::size_t p = 0; p < image.pixel_count(); ++p) {
    for (int c = 0; c < 4; ++c) {
      ASSERT_GE(image.data[p * 4 + c], 0.0f);
      ASSERT_LE(image.data[p * 4 + c], 1.0f);
    }
    min_alpha = std::min(min_alpha, image.data[p * 4 + 3]);
    max_alpha = std::max(max_alpha, image.data[p * 4 + 3]);
  }
  // Transparent background around an opaque object.
  EXPECT_EQ(min_alpha, 0.0f);
  EXPECT_EQ(max_alpha, 1.0f);
  EXPECT_EQ(image.at(0, 0, 3), 0.0f);
}

}  // namespace
}  // namespace splat
