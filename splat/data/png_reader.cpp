#include "splat/data/png_reader.hpp"

#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "splat/core/error.hpp"
#include "splat/data/libpng_handlers.hpp"

namespace splat {
namespace {

// Deflate packs at most ~1,032 bytes into one, so a PNG far smaller than its pixels is a
// header claiming a size its data cannot hold.
constexpr double kMaxDeflateRatio = 1100;
// Ancillary chunks (text, ICC profiles) we never use: none may make libpng allocate more.
constexpr png_alloc_size_t kMaxChunkBytes = png_alloc_size_t(8) << 20;

// libpng's own reader says only "Read Error" when the file ends early.
void read_from_file(png_structp png, png_bytep data, png_size_t length) {
  auto* stream = static_cast<std::FILE*>(png_get_io_ptr(png));
  if (std::fread(data, 1, length, stream) != length)
    png_error(png, std::ferror(stream) ? "cannot read the file" : "the file ends early (truncated)");
}

// One open PNG: libpng's read state and the file, released together.
class PngDecoder {
 public:
  explicit PngDecoder(const std::filesystem::path& file) : file_(file) {
    stream_ = std::fopen(file.c_str(), "rb");
    if (!stream_) throw InputError(file, std::string("cannot open the file: ") + std::strerror(errno));
    png_ = png_create_read_struct(PNG_LIBPNG_VER_STRING, &error_, libpng::on_error, libpng::on_warning);
    if (png_) info_ = png_create_info_struct(png_);
    if (!png_ || !info_) {
      release();
      throw InputError(file, "cannot read the PNG: out of memory");
    }
    png_set_read_fn(png_, stream_, read_from_file);
    png_set_chunk_malloc_max(png_, kMaxChunkBytes);
  }
  ~PngDecoder() { release(); }
  PngDecoder(const PngDecoder&) = delete;
  PngDecoder& operator=(const PngDecoder&) = delete;

  ImageInfo read_header() {
    if (!read_header_or_fail()) fail();
    ImageInfo header{int(width_), int(height_), channels_};
    if (const std::string problem = image_size_problem(width_, height_); !problem.empty())
      throw InputError(file_, "image size " + size_text() + ": " + problem);
    std::error_code ec;
    const std::uintmax_t bytes = std::filesystem::file_size(file_, ec);
    const double raw = double(row_bytes_) * double(height_);
    if (!ec && raw > double(bytes) * kMaxDeflateRatio)
      throw InputError(file_, "image size " + size_text() + " cannot be held in a PNG of " +
                                  std::to_string(bytes) + " bytes (truncated or corrupt)");
    return header;
  }

  // Call after read_header.
  Image read_pixels() {
    std::vector<std::uint8_t> codes(std::size_t(row_bytes_) * height_);
    std::vector<png_bytep> rows(height_);
    for (png_uint_32 y = 0; y < height_; ++y) rows[y] = codes.data() + std::size_t(y) * row_bytes_;
    if (!read_rows_or_fail(rows.data())) fail();
    Image image(int(width_), int(height_), channels_);
    const std::size_t values = image.data.size();
    if (bit_depth_ == 16) {
      constexpr float kScale = 1.0f / 65535.0f;
      std::vector<std::uint16_t> wide(values);
      std::memcpy(wide.data(), codes.data(), values * sizeof(std::uint16_t));
      for (std::size_t i = 0; i < values; ++i) image.data[i] = float(wide[i]) * kScale;
    } else {
      constexpr float kScale = 1.0f / 255.0f;
      for (std::size_t i = 0; i < values; ++i) image.data[i] = float(codes[i]) * kScale;
    }
    return image;
  }

 private:
  // libpng reports an error by jumping back to the setjmp of the function that called it.
  // These two functions hold no object with a destructor, so the jump skips no clean-up.
  bool read_header_or_fail() {
    if (setjmp(png_jmpbuf(png_))) return false;
    png_read_info(png_, info_);
    int color_type = 0;
    png_get_IHDR(png_, info_, &width_, &height_, &bit_depth_, &color_type, nullptr, nullptr, nullptr);
    png_set_expand(png_);  // palette to RGB, 1/2/4-bit grey to 8 bits, tRNS to alpha
    if (bit_depth_ == 16) png_set_swap(png_);  // to the machine's byte order (x86: little)
    png_set_interlace_handling(png_);
    png_read_update_info(png_, info_);
    bit_depth_ = png_get_bit_depth(png_, info_);
    channels_ = png_get_channels(png_, info_);
    row_bytes_ = png_get_rowbytes(png_, info_);
    return true;
  }

  bool read_rows_or_fail(png_bytepp rows) {
    if (setjmp(png_jmpbuf(png_))) return false;
    png_read_image(png_, rows);
    png_read_end(png_, nullptr);  // to the IEND chunk: a file cut after its pixels is damaged too
    return true;
  }

  [[noreturn]] void fail() const {
    throw InputError(file_, std::string("cannot read the PNG: ") + libpng::text_of(error_));
  }

  std::string size_text() const {
    return std::to_string(width_) + " x " + std::to_string(height_) + " x " + std::to_string(channels_);
  }

  void release() {
    if (png_) png_destroy_read_struct(&png_, info_ ? &info_ : nullptr, nullptr);
    if (stream_) std::fclose(stream_);
    png_ = nullptr;
    info_ = nullptr;
    stream_ = nullptr;
  }

  std::filesystem::path file_;
  std::FILE* stream_ = nullptr;
  png_structp png_ = nullptr;
  png_infop info_ = nullptr;
  libpng::ErrorMessage error_;
  png_uint_32 width_ = 0, height_ = 0;
  int bit_depth_ = 0, channels_ = 0;
  png_size_t row_bytes_ = 0;
};

}  // namespace

ImageInfo read_png_header(const std::filesystem::path& file) {
  PngDecoder decoder(file);
  return decoder.read_header();
}

Image read_png(const std::filesystem::path& file) {
  PngDecoder decoder(file);
  decoder.read_header();
  return decoder.read_pixels();
}

}  // namespace splat
