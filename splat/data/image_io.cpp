#include "splat/data/image_io.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "splat/core/atomic_file.hpp"
#include "splat/core/error.hpp"
#include "splat/data/jpeg_reader.hpp"
#include "splat/data/oiio_loader.hpp"
#include "splat/data/resample.hpp"
#include "splat/data/png_reader.hpp"
#include "splat/data/png_writer.hpp"

namespace splat {
namespace {

constexpr int kMaxPngChannels = 4;
constexpr int kMaxImageChannels = 16;
// The formats we read, told apart by their first bytes, whatever the file's name. PNG and
// JPEG have readers of their own (png_reader.hpp, jpeg_reader.hpp); OpenImageIO reads the
// rest, each through its one plugin: told nothing, it would try every plugin it has on a file
// it does not recognise (video through ffmpeg, camera raw, OpenVDB, ...), slow, and far more
// code exposed to a damaged file than photographs and depth maps need.
enum class Reader { png, jpeg, oiio };
struct ImageFormat {
  Reader reader;
  const char* oiio_name;  // the OpenImageIO plugin, for Reader::oiio
  std::string_view magic;
  std::size_t offset = 0;  // where the magic starts
};
constexpr ImageFormat kImageFormats[] = {
    {Reader::png, nullptr, "\x89PNG\r\n\x1a\n"},
    {Reader::jpeg, nullptr, "\xff\xd8\xff"},  // SOI and the first marker after it
    {Reader::oiio, "tiff", std::string_view("II*\0", 4)},
    {Reader::oiio, "tiff", std::string_view("MM\0*", 4)},
    {Reader::oiio, "openexr", std::string_view("\x76\x2f\x31\x01", 4)},
    {Reader::oiio, "bmp", "BM"},
    {Reader::oiio, "webp", "WEBP", 8},
    {Reader::oiio, "hdr", "#?"},
};
constexpr const char* kReadableFormats = "PNG, JPEG, TIFF, OpenEXR, BMP, WebP or Radiance HDR";

const ImageFormat& format_of(const std::filesystem::path& file) {
  std::ifstream stream(file, std::ios::binary);
  if (!stream) throw InputError(file, std::string("cannot open the file: ") + std::strerror(errno));
  char head[16] = {};
  stream.read(head, sizeof head);
  const std::string_view bytes(head, std::size_t(stream.gcount()));
  for (const ImageFormat& format : kImageFormats)
    if (bytes.size() >= format.offset + format.magic.size() &&
        bytes.substr(format.offset, format.magic.size()) == format.magic)
      return format;
  throw InputError(file, std::string("not an image in a format we read (") + kReadableFormats + ")");
}

// OpenEXR's header reader allocates each attribute at the size the file states, before
// reading it (a 1.7 GB allocation from a 60-byte file, found by the image fuzz target): the
// header's attributes (name, type, 32-bit size, value; an empty name ends them) are walked
// here first, and a size beyond the file's bytes is an error. Only the names and sizes are
// read; the values are skipped.
void check_exr_attribute_sizes(const std::filesystem::path& file) {
  constexpr std::size_t kMaxNameBytes = 255;
  std::ifstream stream(file, std::ios::binary | std::ios::ate);
  const auto file_bytes = std::uint64_t(std::max<std::streamoff>(stream.tellg(), 0));
  std::uint64_t at = 8;  // magic and version
  stream.seekg(std::streamoff(at));
  const auto read_name = [&]() -> std::size_t {
    std::size_t length = 0;
    for (char c = 0; stream.get(c) && c != '\0'; ++length)
      if (length == kMaxNameBytes) throw InputError(file, "OpenEXR header is corrupt (a name over 255 bytes)");
    if (!stream) throw InputError(file, "OpenEXR header is truncated");
    at += length + 1;
    return length;
  };
  for (;;) {
    if (read_name() == 0) return;
    (void)read_name();  // the type
    unsigned char size_bytes[4] = {};
    if (!stream.read(reinterpret_cast<char*>(size_bytes), 4)) throw InputError(file, "OpenEXR header is truncated");
    at += 4;
    const std::uint32_t size = std::uint32_t(size_bytes[0]) | std::uint32_t(size_bytes[1]) << 8 |
                               std::uint32_t(size_bytes[2]) << 16 | std::uint32_t(size_bytes[3]) << 24;
    if (size > file_bytes - at)
      throw InputError(file, "OpenEXR header attribute ending at byte " + std::to_string(at) + " claims " +
                                 std::to_string(size) + " bytes, more than the file has left");
    at += size;
    stream.seekg(std::streamoff(at));
  }
}

using oiio_plugin::Failure;
using oiio_plugin::Outcome;

// A file open in the OpenImageIO plugin, closed with it.
struct PluginReaderCloser {
  const oiio_plugin::Api* api;
  void operator()(oiio_plugin::Reader* reader) const { api->close(reader); }
};
using PluginReader = std::unique_ptr<oiio_plugin::Reader, PluginReaderCloser>;

// Opens `file` with the plugin's `format` reader and checks its size against the image limits.
PluginReader open_input(const std::filesystem::path& file, const char* format, oiio_plugin::Spec& spec) {
  if (std::string_view(format) == "openexr") check_exr_attribute_sizes(file);
  const oiio_plugin::Api& api = oiio_plugin_for(file);
  Outcome outcome;
  PluginReader in(api.open(file.string(), format, spec, outcome), PluginReaderCloser{&api});
  if (!in) {
    if (outcome.failure == Failure::no_reader)
      throw InputError(file, std::string("no ") + format + " reader: " + outcome.message);
    throw InputError(file, "cannot read image: " + outcome.message);
  }
  const std::string size = std::to_string(spec.width) + " x " + std::to_string(spec.height) + " x " +
                           std::to_string(spec.channels);
  if (const std::string problem = image_size_problem(spec.width, spec.height); !problem.empty())
    throw InputError(file, "image size " + size + ": " + problem);
  if (spec.channels < 1 || spec.channels > kMaxImageChannels)
    throw InputError(file, "image size " + size + ": 1 to " + std::to_string(kMaxImageChannels) + " channels");
  if (spec.depth > 1 || spec.deep)
    throw InputError(file, "volume and deep images are not supported");
  return in;
}

void check_image_shape(const Image& image, const std::filesystem::path& file) {
  const bool consistent = image.width > 0 && image.height > 0 && image.channels > 0 &&
                          image.data.size() == image.pixel_count() * std::size_t(image.channels);
  if (!consistent)
    throw ArgumentError(file.string() + ": cannot write an empty or inconsistent image (" +
                        std::to_string(image.width) + " x " + std::to_string(image.height) +
                        " x " + std::to_string(image.channels) + ", " +
                        std::to_string(image.data.size()) + " values)");
}

// Clamps to [0, 1] and rounds to the nearest code; NaN has no sensible code and becomes 0.
template <class Code>
std::vector<Code> quantise(const Image& image) {
  constexpr float kMaxCode = float(std::numeric_limits<Code>::max());
  std::vector<Code> codes(image.data.size());
  for (std::size_t i = 0; i < codes.size(); ++i) {
    float v = image.data[i];
    v = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;  // also maps NaN to 0
    codes[i] = Code(std::lround(v * kMaxCode));
  }
  return codes;
}

// "cannot create image: ...": where the folder is missing, in those plain words (OpenImageIO's
// own message would name the temporary).
[[noreturn]] void throw_cannot_create(const std::filesystem::path& file, const std::string& message) {
  const std::filesystem::path folder = file.parent_path();
  if (!folder.empty() && !std::filesystem::is_directory(folder))
    throw InputError(file, "cannot create image: folder " + folder.string() + " does not exist");
  throw InputError(file, "cannot create image: " + message);
}

// Writes `pixels` (of `type`, interleaved as `image` is) to `temp` through the OpenImageIO
// plugin as `format`, which is a format name or a file name to infer it from. Errors name
// `file`, the path the user asked for.
void write_with_oiio(const std::filesystem::path& file, const std::filesystem::path& temp, const std::string& format,
                     const Image& image, oiio_plugin::PixelType type, const void* pixels) {
  const oiio_plugin::Api& api = oiio_plugin_for(file);
  const oiio_plugin::Spec spec{image.width, image.height, image.channels};
  Outcome outcome;
  if (api.write(temp.string(), format, spec, type, pixels, outcome)) return;
  switch (outcome.failure) {
    case Failure::no_writer: throw InputError(file, "no image writer for this format: " + outcome.message);
    case Failure::cannot_create: throw_cannot_create(file, outcome.message);
    case Failure::cannot_write: throw InputError(file, "cannot write image: " + outcome.message);
    case Failure::cannot_finish: throw InputError(file, "cannot finish image: " + outcome.message);
    default: throw InputError(file, outcome.message);  // narrower_type: the message says it all
  }
}

}  // namespace

Image read_image(const std::filesystem::path& file) {
  const ImageFormat& format = format_of(file);
  if (format.reader == Reader::png) return read_png(file);
  if (format.reader == Reader::jpeg) return read_jpeg(file);
  oiio_plugin::Spec spec;
  const PluginReader in = open_input(file, format.oiio_name, spec);
  Image image(spec.width, spec.height, spec.channels);
  Outcome outcome;
  if (!oiio_plugin_for(file).read_float(in.get(), image.data.data(), outcome)) {
    if (outcome.failure == Failure::damaged_data) throw InputError(file, "damaged image data: " + outcome.message);
    throw InputError(file, "cannot decode image: " + outcome.message);
  }
  return image;
}

Image read_image_reduced(const std::filesystem::path& file, int reduction) {
  if (reduction < 1) throw ArgumentError("image reduction must be 1 or more, not " + std::to_string(reduction));
  if (reduction == 1) return read_image(file);
  Image image;
  int stored_width = 0, stored_height = 0;
  if (format_of(file).reader == Reader::jpeg) {
    // The largest of libjpeg's reductions not beyond ours decodes the fewest pixels; an area
    // average finishes the rest (on whole blocks of decoded pixels when it divides ours).
    unsigned denominator = 8;
    while (int(denominator) > reduction) denominator /= 2;
    ReducedJpeg reduced = read_jpeg_reduced(file, denominator);
    stored_width = reduced.stored.width;
    stored_height = reduced.stored.height;
    image = std::move(reduced.image);
  } else {
    image = read_image(file);
    stored_width = image.width;
    stored_height = image.height;
  }
  const int width = stored_width / reduction, height = stored_height / reduction;
  if (width < 1 || height < 1)
    throw InputError(file, "image is " + std::to_string(stored_width) + " x " + std::to_string(stored_height) +
                               ", too small to reduce by " + std::to_string(reduction));
  if (image.width == width && image.height == height) return image;
  return resample_area(image, width, height);
}

ImageInfo read_image_stored_size(const std::filesystem::path& file) {
  if (format_of(file).reader == Reader::jpeg) return read_jpeg_stored_size(file);
  return read_image_info(file);
}

ImageInfo read_image_info(const std::filesystem::path& file) {
  const ImageFormat& format = format_of(file);
  if (format.reader == Reader::png) return read_png_header(file);
  if (format.reader == Reader::jpeg) return read_jpeg_header(file);
  oiio_plugin::Spec spec;
  (void)open_input(file, format.oiio_name, spec);
  return {spec.width, spec.height, spec.channels};
}

std::vector<std::uint8_t> image_codes_8bit(const Image& image) { return quantise<std::uint8_t>(image); }

void write_png(const Image& image, const std::filesystem::path& file, int bits) {
  check_image_shape(image, file);
  if (bits != 8 && bits != 16)
    throw ArgumentError(file.string() + ": PNG bit depth must be 8 or 16, not " +
                        std::to_string(bits));
  if (image.channels > kMaxPngChannels)
    throw ArgumentError(file.string() + ": PNG holds at most 4 channels, not " +
                        std::to_string(image.channels));
  // Both depths through one writer: `codes` is the vector of either width.
  auto write = [&](const auto& codes) {
    write_stream_atomically(file, [&](std::ostream& out) {
      write_png_codes(file, out, image.width, image.height, image.channels, bits, codes.data());
    });
  };
  if (bits == 8)
    write(quantise<std::uint8_t>(image));
  else
    write(quantise<std::uint16_t>(image));
}

void write_float_image(const Image& image, const std::filesystem::path& file) {
  check_image_shape(image, file);
  write_atomically(file, [&](const std::filesystem::path& temp) {
    // The temporary keeps the extension, but the user's name is the clearer one to infer from.
    write_with_oiio(file, temp, file.string(), image, oiio_plugin::PixelType::float32, image.data.data());
  });
}

}  // namespace splat
