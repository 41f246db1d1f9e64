#pragma once
// The interface between the library and its OpenImageIO plugin (splat/data/plugin/, built as
// lib/splat/libsplat_oiio.so beside the programs' bin/). Only TIFF, OpenEXR, BMP, WebP and Radiance HDR go
// through OpenImageIO (PNG and JPEG have readers and a writer of their own), and Debian's
// OpenImageIO brings some 260 shared libraries with it (GDAL, OpenCV, DCMTK, ...): linked into
// every program, resolving their symbols took 0.3 s of every start, 0.6 s under the sanitizers.
// Loaded with dlopen on the first such file instead, it costs only the runs that read or
// write one.
//
// Both sides are compiled with the same compiler and standard library, so the functions take
// std types; they report failures in an Outcome rather than throwing, and the library words
// the error (naming the user's file) as before.
#include <string>
#include <vector>

namespace splat::oiio_plugin {

// Raised when a function's signature or meaning changes: a stale plugin is refused.
constexpr int kApiVersion = 1;

// What failed, for the caller to word; `message` is OpenImageIO's (one line).
enum class Failure { none, no_reader, cannot_open, cannot_decode, damaged_data, no_writer, cannot_create,
                     cannot_write, cannot_finish, narrower_type };
struct Outcome {
  Failure failure = Failure::none;
  std::string message;
};

struct Spec {
  int width = 0, height = 0, channels = 0;
  int depth = 1;  // > 1: a volume
  bool deep = false;
};

enum class PixelType { uint8, uint16, float32 };

struct Reader;  // one open file (the plugin's)

struct Api {
  int version;
  // Opens `file` with OpenImageIO's plugin `format` ("tiff", "openexr", ...), alpha left
  // straight; fills `spec`. Null on failure (no_reader, cannot_open).
  Reader* (*open)(const std::string& file, const char* format, Spec& spec, Outcome& outcome);
  // Every channel as float (integer codes / max code) into `pixels` (width·height·channels).
  // False on failure (cannot_decode, damaged_data).
  bool (*read_float)(Reader* reader, float* pixels, Outcome& outcome);
  void (*close)(Reader* reader);
  // Writes `pixels` (interleaved, `type`) to `temp` as `format`: a format name or a file
  // name to infer it from; straight alpha. False on failure (no_writer, cannot_create,
  // cannot_write, cannot_finish, narrower_type).
  bool (*write)(const std::string& temp, const std::string& format, const Spec& spec, PixelType type,
                const void* pixels, Outcome& outcome);
};

}  // namespace splat::oiio_plugin

// The plugin's one exported symbol.
extern "C" const splat::oiio_plugin::Api* splat_oiio_plugin_api();
