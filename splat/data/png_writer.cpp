#include "splat/data/png_writer.hpp"

#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstring>
#include <string>
#include <vector>

#include "splat/core/error.hpp"
#include "splat/data/libpng_handlers.hpp"

namespace splat {
namespace {

// libpng's own writer says only "Write Error"; the system's reason (a full disk) is clearer.
void write_to_stream(png_structp png, png_bytep data, png_size_t length) {
  auto* out = static_cast<std::ostream*>(png_get_io_ptr(png));
  errno = 0;
  if (!out->write(reinterpret_cast<const char*>(data), std::streamsize(length)))
    png_error(png, errno ? std::strerror(errno) : "the stream refused the bytes");
}

// The caller flushes and closes the stream, and checks it then (write_stream_atomically).
void flush_stream(png_structp) {}

int color_type_of(int channels) {
  switch (channels) {
    case 1: return PNG_COLOR_TYPE_GRAY;
    case 2: return PNG_COLOR_TYPE_GRAY_ALPHA;
    case 3: return PNG_COLOR_TYPE_RGB;
    default: return PNG_COLOR_TYPE_RGB_ALPHA;
  }
}

// libpng's write state.
class PngEncoder {
 public:
  PngEncoder(const std::filesystem::path& file, std::ostream& out) : file_(file) {
    png_ = png_create_write_struct(PNG_LIBPNG_VER_STRING, &error_, libpng::on_error, libpng::on_warning);
    if (png_) info_ = png_create_info_struct(png_);
    if (!png_ || !info_) {
      release();
      throw InputError(file, "cannot write image: out of memory");
    }
    png_set_write_fn(png_, &out, write_to_stream, flush_stream);
  }
  ~PngEncoder() { release(); }
  PngEncoder(const PngEncoder&) = delete;
  PngEncoder& operator=(const PngEncoder&) = delete;

  void write(int width, int height, int channels, int bits, const void* codes) {
    const std::size_t row_bytes = std::size_t(width) * channels * (bits / 8);
    std::vector<png_bytep> rows(static_cast<std::size_t>(height));
    for (int y = 0; y < height; ++y)
      rows[std::size_t(y)] = const_cast<png_bytep>(static_cast<const png_byte*>(codes)) + std::size_t(y) * row_bytes;
    if (!write_or_fail(width, height, color_type_of(channels), bits, rows.data()))
      throw InputError(file_, std::string("cannot write image: ") + libpng::text_of(error_));
  }

 private:
  // libpng reports an error by jumping back here; this function holds no object with a
  // destructor, so the jump skips no clean-up. (libpng reads the rows, it does not write them.)
  bool write_or_fail(int width, int height, int color_type, int bits, png_bytepp rows) {
    if (setjmp(png_jmpbuf(png_))) return false;
    png_set_IHDR(png_, info_, png_uint_32(width), png_uint_32(height), bits, color_type, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png_, info_);
    if (bits == 16) png_set_swap(png_);  // PNG stores big-endian; our codes are the machine's (x86: little)
    png_write_image(png_, rows);
    png_write_end(png_, nullptr);
    return true;
  }

  void release() {
    if (png_) png_destroy_write_struct(&png_, info_ ? &info_ : nullptr);
    png_ = nullptr;
    info_ = nullptr;
  }

  std::filesystem::path file_;
  png_structp png_ = nullptr;
  png_infop info_ = nullptr;
  libpng::ErrorMessage error_;
};

}  // namespace

void write_png_codes(const std::filesystem::path& file, std::ostream& out, int width, int height, int channels,
                     int bits, const void* codes) {
  PngEncoder encoder(file, out);
  encoder.write(width, height, channels, bits, codes);
}

}  // namespace splat
