// The OpenImageIO plugin (splat/data/oiio_plugin.hpp): reads and writes the formats the
// library leaves to OpenImageIO. Built as a module of its own (libsplat_oiio.so), loaded by
// splat/data/oiio_loader.cpp on first use; nothing else links OpenImageIO.
#include <OpenImageIO/imageio.h>

#include <memory>
#include <string>

#include "splat/data/oiio_plugin.hpp"

namespace splat::oiio_plugin {
namespace {

// OpenImageIO premultiplies alpha into the colour of PNG/TIFF/... on read, and divides it out
// again on write, unless told the data are straight ("unassociated"). We want the stored
// values untouched in both directions.
constexpr const char* kUnassociatedAlpha = "oiio:UnassociatedAlpha";

// OpenImageIO may report one failure over several lines (each layer adds its own); our
// errors are one line.
std::string one_line(std::string message) {
  while (!message.empty() && message.back() == '\n') message.pop_back();
  for (std::size_t at = message.find('\n'); at != std::string::npos; at = message.find('\n', at))
    message.replace(at, 1, "; ");
  return message.empty() ? "unknown OpenImageIO error" : message;
}

// OpenImageIO keeps one pending error per thread for failures that have no ImageInput or
// ImageOutput to report them. Reading it clears it, so a message can never surface in a
// later, unrelated call.
std::string take_global_error() { return one_line(OIIO::geterror()); }

void discard_stale_global_error() {
  if (OIIO::has_error()) (void)OIIO::geterror();
}

template <class T>
std::string take_error(const T& io) {
  return one_line(io.geterror());
}

bool fail(Outcome& outcome, Failure failure, std::string message) {
  outcome = {failure, std::move(message)};
  return false;
}

OIIO::TypeDesc type_of(PixelType type) {
  switch (type) {
    case PixelType::uint8: return OIIO::TypeDesc::UINT8;
    case PixelType::uint16: return OIIO::TypeDesc::UINT16;
    case PixelType::float32: break;
  }
  return OIIO::TypeDesc::FLOAT;
}

}  // namespace

struct Reader {
  std::unique_ptr<OIIO::ImageInput> input;
};

namespace {

Reader* open(const std::string& file, const char* format, Spec& spec, Outcome& outcome) {
  discard_stale_global_error();
  OIIO::ImageSpec config;
  config.attribute(kUnassociatedAlpha, 1);
  auto in = OIIO::ImageInput::create(format, /*do_open=*/false, &config);
  if (!in) {
    fail(outcome, Failure::no_reader, take_global_error());
    return nullptr;
  }
  OIIO::ImageSpec opened;
  if (!in->open(file, opened, config)) {
    fail(outcome, Failure::cannot_open, take_error(*in));
    return nullptr;
  }
  const OIIO::ImageSpec& s = in->spec();
  spec = {s.width, s.height, s.nchannels, s.depth, s.deep};
  return new Reader{std::move(in)};
}

bool read_float(Reader* reader, float* pixels, Outcome& outcome) {
  OIIO::ImageInput& in = *reader->input;
  // Asking for float makes OpenImageIO map integer codes to [0, 1] (code / max code).
  if (!in.read_image(/*subimage=*/0, /*miplevel=*/0, /*chbegin=*/0, in.spec().nchannels, OIIO::TypeDesc::FLOAT,
                     pixels)) {
    return fail(outcome, Failure::cannot_decode, take_error(in));  // close() ends it
  }
  // A decoder that met damaged data may still fill the image (libjpeg pads a truncated
  // JPEG with grey) and only leave a message behind: that image is not the photograph.
  // (OpenImageIO 2.4's has_error() does not see that message; geterror() does.)
  if (std::string message = in.geterror(); !message.empty())
    return fail(outcome, Failure::damaged_data, one_line(message));
  return true;
}

void close(Reader* reader) {
  if (!reader) return;
  reader->input->close();
  (void)reader->input->geterror();  // nothing left pending for the destructor
  delete reader;
}

bool write(const std::string& temp, const std::string& format, const Spec& spec, PixelType type,
           const void* pixels, Outcome& outcome) {
  discard_stale_global_error();
  OIIO::ImageSpec out_spec(spec.width, spec.height, spec.channels, type_of(type));
  out_spec.attribute(kUnassociatedAlpha, 1);
  auto out = OIIO::ImageOutput::create(format);
  if (!out) return fail(outcome, Failure::no_writer, take_global_error());
  if (!out->open(temp, out_spec)) return fail(outcome, Failure::cannot_create, take_error(*out));
  if (!out->write_image(type_of(type), pixels)) {
    const std::string message = take_error(*out);
    out->close();
    (void)out->geterror();
    return fail(outcome, Failure::cannot_write, message);
  }
  if (!out->close()) return fail(outcome, Failure::cannot_finish, take_error(*out));
  // Some writers quietly store a narrower type than asked (PNG has no floats). Checked only
  // now because abandoning a half-open file makes libpng print; the caller discards the file.
  if (out->spec().format != out_spec.format)
    return fail(outcome, Failure::narrower_type,
                std::string("this format cannot store ") + out_spec.format.c_str() + " pixels (it would write " +
                    out->spec().format.c_str() + ")");
  return true;
}

constexpr Api kApi{kApiVersion, open, read_float, close, write};

}  // namespace
}  // namespace splat::oiio_plugin

extern "C" __attribute__((visibility("default"))) const splat::oiio_plugin::Api* splat_oiio_plugin_api() {
  return &splat::oiio_plugin::kApi;
}
