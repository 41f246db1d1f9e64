// Sizes read from a file are checked against stated limits, and against the bytes present,
// before anything is allocated for them: a tiny PNG whose header claims 12000 x 12000 pixels,
// or a transforms file asking for a 65536 x 65536 image, is one clean error naming the file.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <string>

#include "splat/core/error.hpp"
#include "splat/data/image_io.hpp"
#include "splat/data/transforms_json.hpp"
#include "tests/cli_support.hpp"
#include "tests/data/png_bytes.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

// A small PNG whose header claims width x height (with a correct CRC), over a few pixels.
fs::path png_claiming(const fs::path& dir, std::uint32_t width, std::uint32_t height) {
  const fs::path file = dir / "claims.png";
  test::write_text(file, test::kPngSignature + test::png_ihdr(width, height, 8, 2) +
                             test::png_idat(std::string(4 * (1 + 4 * 3), '\0')) + test::png_chunk("IEND", ""));
  return file;
}

template <class Read>
void expect_input_error(const Read& read, const fs::path& file, const std::string& expected) {
  try {
    read();
    ADD_FAILURE() << file << " was accepted";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(file.string() + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(expected), std::string::npos) << message;
  }
}

TEST(InputLimits, APngClaimingMorePixelsThanItsBytesHoldIsRefusedBeforeDecoding) {
  const fs::path dir = test::scratch_dir("input_limits_png");
  // Within the pixel limit (4000 x 4000 x 3 bytes), but not in a file of a few dozen bytes.
  const fs::path file = png_claiming(dir, 4000, 4000);
  EXPECT_LT(fs::file_size(file), 200u);
  expect_input_error([&] { read_image(file); }, file, "cannot be held");
  expect_input_error([&] { read_image_info(file); }, file, "cannot be held");
  // The size the report found (12000 x 12000, 2.4 GB as floats) is past the pixel limit too.
  const fs::path larger = png_claiming(dir, 12000, 12000);
  expect_input_error([&] { read_image(larger); }, larger, "pixels");
}

TEST(InputLimits, ImagesLargerThanThePixelLimitAreRefused) {
  const fs::path dir = test::scratch_dir("input_limits_pixels");
  const fs::path file = png_claiming(dir, 60000, 60000);  // each side allowed, not both
  expect_input_error([&] { read_image_info(file); }, file, "pixels");
}

TEST(InputLimits, TransformsAskingForAHugeImageNameTheFileAndTheKeys) {
  const fs::path dir = test::scratch_dir("input_limits_transforms");
  const fs::path file = dir / "transforms.json";
  test::write_text(file, R"({"camera_angle_x": 0.8, "w": 65536, "h": 65536, "frames": [
    {"file_path": "a", "transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,4],[0,0,0,1]]}]})");
  expect_input_error([&] { load_transforms(file); }, file, "\"w\"");
}

}  // namespace
}  // namespace splat
