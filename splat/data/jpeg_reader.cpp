#include "splat/data/jpeg_reader.hpp"

// jpeglib.h needs FILE and size_t declared first.
#include <cstddef>
#include <cstdio>

#include <jpeglib.h>

#include <cerrno>
#include <csetjmp>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "splat/core/error.hpp"

namespace splat {
namespace {

// libjpeg's error manager, extended with where to jump and the message to report.
struct ErrorManager {
  jpeg_error_mgr library;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX] = {};
};

[[noreturn]] void on_libjpeg_error(j_common_ptr info) {
  auto* errors = reinterpret_cast<ErrorManager*>(info->err);
  (*info->err->format_message)(info, errors->message);
  std::longjmp(errors->jump, 1);
}

// libjpeg reports damaged data ("Premature end of JPEG file", "Corrupt JPEG data") as
// warnings and goes on with grey: the first one is kept, and the read fails after decoding.
// Trace messages (level > 0) are dropped; nothing is printed.
void on_libjpeg_message(j_common_ptr info, int level) {
  auto* errors = reinterpret_cast<ErrorManager*>(info->err);
  if (level >= 0) return;
  if (info->err->num_warnings++ == 0) (*info->err->format_message)(info, errors->message);
}

// One open JPEG: libjpeg's decompressor and the file, released together.
class JpegDecoder {
 public:
  explicit JpegDecoder(const std::filesystem::path& file) : file_(file) {
    stream_ = std::fopen(file.c_str(), "rb");
    if (!stream_) throw InputError(file, std::string("cannot open the file: ") + std::strerror(errno));
    info_.err = jpeg_std_error(&errors_.library);
    errors_.library.error_exit = on_libjpeg_error;
    errors_.library.emit_message = on_libjpeg_message;
    if (!create_or_fail()) {
      std::fclose(stream_);
      fail();
    }
  }
  ~JpegDecoder() {
    jpeg_destroy_decompress(&info_);
    std::fclose(stream_);
  }
  JpegDecoder(const JpegDecoder&) = delete;
  JpegDecoder& operator=(const JpegDecoder&) = delete;

  // The size decoded at 1/`denominator` (1, 2, 4 or 8: libjpeg's DCT scaling, each side
  // rounded up), checked against the image limits.
  ImageInfo read_header(unsigned denominator = 1) {
    if (!read_header_or_fail(denominator)) fail();
    const ImageInfo header{int(info_.output_width), int(info_.output_height), info_.output_components};
    if (const std::string problem = image_size_problem(header.width, header.height); !problem.empty())
      throw InputError(file_, "image size " + std::to_string(header.width) + " x " + std::to_string(header.height) +
                                  ": " + problem);
    return header;
  }

  // Call after read_header.
  Image read_pixels(const ImageInfo& header) {
    std::vector<JSAMPLE> codes(std::size_t(header.width) * header.height * header.channels);
    if (!read_rows_or_fail(codes.data())) fail();
    if (errors_.library.num_warnings > 0)
      throw InputError(file_, std::string("damaged image data: ") + errors_.message);
    Image image(header.width, header.height, header.channels);
    constexpr float kScale = 1.0f / 255.0f;
    for (std::size_t i = 0; i < codes.size(); ++i) image.data[i] = float(codes[i]) * kScale;
    return image;
  }

  // libjpeg reports an error by jumping back to the setjmp of the function that called it.
  // These functions hold no object with a destructor, so the jump skips no clean-up.
  bool create_or_fail() {
    if (setjmp(errors_.jump)) return false;
    jpeg_create_decompress(&info_);
    jpeg_stdio_src(&info_, stream_);
    return true;
  }

  // The size stored in the file (after read_header).
  ImageInfo stored_size() const { return {int(info_.image_width), int(info_.image_height), info_.num_components}; }

 private:
  bool read_header_or_fail(unsigned denominator) {
    if (setjmp(errors_.jump)) return false;
    jpeg_read_header(&info_, TRUE);
    info_.scale_num = 1;
    info_.scale_denom = denominator;
    // Grey stays grey; everything else is asked for as RGB (libjpeg refuses CMYK to RGB).
    info_.out_color_space = info_.jpeg_color_space == JCS_GRAYSCALE ? JCS_GRAYSCALE : JCS_RGB;
    jpeg_calc_output_dimensions(&info_);
    return true;
  }

  bool read_rows_or_fail(JSAMPLE* codes) {
    if (setjmp(errors_.jump)) return false;
    jpeg_start_decompress(&info_);
    const std::size_t row_values = std::size_t(info_.output_width) * info_.output_components;
    while (info_.output_scanline < info_.output_height) {
      JSAMPROW row = codes + std::size_t(info_.output_scanline) * row_values;
      jpeg_read_scanlines(&info_, &row, 1);
    }
    jpeg_finish_decompress(&info_);
    return true;
  }

  [[noreturn]] void fail() const {
    throw InputError(file_, std::string("cannot read the JPEG: ") +
                                (errors_.message[0] ? errors_.message : "unknown libjpeg error"));
  }

  std::filesystem::path file_;
  std::FILE* stream_ = nullptr;
  jpeg_decompress_struct info_{};
  ErrorManager errors_;
};

}  // namespace

ImageInfo read_jpeg_header(const std::filesystem::path& file) {
  JpegDecoder decoder(file);
  return decoder.read_header();
}

Image read_jpeg(const std::filesystem::path& file) {
  JpegDecoder decoder(file);
  return decoder.read_pixels(decoder.read_header());
}

ImageInfo read_jpeg_stored_size(const std::filesystem::path& file) {
  JpegDecoder decoder(file);
  decoder.read_header(8);  // the smallest decoded size: only a side beyond 8 × 65,536 fails
  return decoder.stored_size();
}

ReducedJpeg read_jpeg_reduced(const std::filesystem::path& file, unsigned denominator) {
  if (denominator != 1 && denominator != 2 && denominator != 4 && denominator != 8)
    throw ArgumentError("JPEG reduction must be 1, 2, 4 or 8");
  JpegDecoder decoder(file);
  const ImageInfo decoded = decoder.read_header(denominator);
  return {decoder.stored_size(), decoder.read_pixels(decoded)};
}

}  // namespace splat
