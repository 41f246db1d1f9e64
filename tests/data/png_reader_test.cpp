// PNGs are read with libpng directly (png_reader.hpp): every kind of PNG comes back as the
// codes it stores, scaled as OpenImageIO scales them, and a damaged PNG is one error line
// naming the file, with nothing printed by libpng itself.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "splat/core/error.hpp"
#include "splat/data/image_io.hpp"
#include "splat/data/png_reader.hpp"
#include "tests/data/png_bytes.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

constexpr int kGrey = 0, kRgb = 2, kPalette = 3, kGreyAlpha = 4, kRgba = 6;

// Each test writes into its own folder: ctest runs the tests as parallel processes.
class PngReader : public testing::Test {
 protected:
  fs::path write_png_bytes(const std::string& name, const std::string& bytes) const {
    const fs::path file = dir_ / name;
    test::write_text(file, bytes);
    return file;
  }
  const fs::path dir_ = test::scratch_dir(std::string("png_reader_") +
                                          testing::UnitTest::GetInstance()->current_test_info()->name());
};

// `rows` copies of one scanline (filter byte 0, then `line`).
std::string repeated_rows(const std::string& line, int rows) {
  std::string scanlines;
  for (int y = 0; y < rows; ++y) scanlines += '\0' + line;
  return scanlines;
}

std::vector<float> first_row(const Image& image) {
  return {image.data.begin(), image.data.begin() + std::ptrdiff_t(image.width * image.channels)};
}

constexpr float kByte = 1.0f / 255.0f;

TEST_F(PngReader, EightBitCodesAreScaledByOneOver255) {
  std::string line;
  for (int code = 0; code < 256; ++code) line += char(code);
  const fs::path file = write_png_bytes("grey8.png", test::png_file(256, 2, 8, kGrey, repeated_rows(line, 2)));
  const Image image = read_image(file);
  ASSERT_EQ(image.channels, 1);
  for (int code = 0; code < 256; ++code) EXPECT_EQ(image.data[std::size_t(code)], float(code) * kByte) << code;
}

TEST_F(PngReader, SixteenBitCodesKeepTheirPrecision) {
  const std::vector<unsigned> codes = {0, 1, 257, 32768, 65534, 65535};
  std::string line;
  for (unsigned code : codes) line += {char(code >> 8), char(code & 0xff)};
  const Image image = read_image(write_png_bytes("grey16.png", test::png_file(6, 1, 16, kGrey, repeated_rows(line, 1))));
  for (std::size_t i = 0; i < codes.size(); ++i) EXPECT_EQ(image.data[i], float(codes[i]) * (1.0f / 65535.0f));
}

TEST_F(PngReader, LowBitDepthGreyExpandsToFullRange) {
  // 1-bit: 1 0 1 1 0 0 1 0 → 255 0 255 255 0 0 255 0.
  const Image image = read_image(write_png_bytes("grey1.png", test::png_file(8, 1, 1, kGrey, repeated_rows("\xb2", 1))));
  EXPECT_EQ(first_row(image), (std::vector<float>{1, 0, 1, 1, 0, 0, 1, 0}));
}

TEST_F(PngReader, PaletteBecomesRgbAndTransparencyAnAlphaChannel) {
  const std::string palette = test::png_chunk("PLTE", std::string("\x0a\x14\x1e\xc8\x64\x32", 6));
  const std::string pixels = repeated_rows(std::string("\x00\x01", 2), 1);
  const Image rgb = read_image(write_png_bytes("palette.png", test::png_file(2, 1, 8, kPalette, pixels, palette)));
  ASSERT_EQ(rgb.channels, 3);
  EXPECT_EQ(first_row(rgb), (std::vector<float>{10 * kByte, 20 * kByte, 30 * kByte, 200 * kByte, 100 * kByte, 50 * kByte}));
  const std::string transparency = test::png_chunk("tRNS", std::string("\x80", 1));  // entry 0 half, entry 1 opaque
  const Image rgba = read_image(write_png_bytes("palette_trns.png", test::png_file(2, 1, 8, kPalette, pixels, palette + transparency)));
  ASSERT_EQ(rgba.channels, 4);
  EXPECT_EQ(rgba.data[3], 128 * kByte);
  EXPECT_EQ(rgba.data[7], 1.0f);
}

TEST_F(PngReader, ChannelCountsAndAlphaAreKeptStraight) {
  // Grey + alpha and RGBA: alpha is not multiplied into the colour.
  const Image grey_alpha = read_image(write_png_bytes("ga.png", test::png_file(1, 1, 8, kGreyAlpha, repeated_rows("\xc8\x40", 1))));
  EXPECT_EQ(first_row(grey_alpha), (std::vector<float>{200 * kByte, 64 * kByte}));
  const Image rgba = read_image(write_png_bytes("rgba.png", test::png_file(1, 1, 8, kRgba, repeated_rows(std::string("\xff\x80\x01\x00", 4), 1))));
  EXPECT_EQ(first_row(rgba), (std::vector<float>{1.0f, 128 * kByte, 1 * kByte, 0.0f}));
  const ImageInfo info = read_image_info(write_png_bytes("rgb.png", test::png_file(3, 2, 8, kRgb, repeated_rows("abcdefghi", 2))));
  EXPECT_EQ(info.width, 3);
  EXPECT_EQ(info.height, 2);
  EXPECT_EQ(info.channels, 3);
}

TEST_F(PngReader, DamagedFilesAreOneLineNamingTheFileAndLibpngPrintsNothing) {
  const std::string rows = repeated_rows(std::string(8 * 3, '\x40'), 8);
  const std::string good = test::png_file(8, 8, 8, kRgb, rows);
  std::string bad_crc = good;
  bad_crc[30] ^= 0x01;  // inside IHDR's data: its CRC no longer matches
  const std::string idat = test::png_idat(rows);
  struct Case {
    std::string name, bytes, expected;
    bool header_is_damaged;  // else only the pixels are, which read_image_info does not decode
  };
  const std::vector<Case> cases = {
      {"truncated.png", good.substr(0, 8 + 25 + idat.size() / 2), "truncated", false},
      {"header_only.png", good.substr(0, 20), "truncated", true},
      {"bad_crc.png", bad_crc, "CRC", true},
      {"not_deflate.png", test::kPngSignature + test::png_ihdr(8, 8, 8, kRgb) + test::png_chunk("IDAT", "not deflate data") + test::png_chunk("IEND", ""), "IDAT", false},
      {"unknown_critical.png", test::kPngSignature + test::png_ihdr(8, 8, 8, kRgb) + test::png_chunk("ABCD", "xy") + idat + test::png_chunk("IEND", ""), "ABCD", true},
      {"bad_depth.png", test::png_file(8, 8, 7, kRgb, rows), "IHDR", true},
      {"zero_width.png", test::png_file(0, 8, 8, kRgb, rows), "width", true},
  };
  for (const Case& c : cases) {
    const fs::path file = write_png_bytes(c.name, c.bytes);
    for (bool header_only : {false, true}) {
      if (header_only && !c.header_is_damaged) continue;
      testing::internal::CaptureStderr();
      try {
        if (header_only)
          (void)read_image_info(file);
        else
          (void)read_image(file);
        ADD_FAILURE() << c.name << " was accepted";
      } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.rfind(file.string() + ": ", 0), 0u) << message;
        EXPECT_NE(message.find(c.expected), std::string::npos) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
      }
      EXPECT_EQ(testing::internal::GetCapturedStderr(), "") << c.name;
    }
  }
}

TEST_F(PngReader, TheFirstBytesNotTheNameDecideWhichReaderReadsAFile) {
  const ImageInfo info = read_image_info(write_png_bytes("named.jpg", test::png_file(1, 1, 8, kGrey, repeated_rows("\x01", 1))));
  EXPECT_EQ(info.width, 1);
  EXPECT_EQ(info.channels, 1);
  const fs::path jpeg_named_png = write_png_bytes("named.png", "\xff\xd8\xff not a jpeg either");
  try {
    read_image_info(jpeg_named_png);
    ADD_FAILURE() << "a damaged JPEG was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("JPEG"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace splat
