#pragma once
// PNG files written with libpng directly (the reader's counterpart, png_reader.hpp): the
// images every program writes need no OpenImageIO (oiio_plugin.hpp says why that matters).
#include <filesystem>
#include <ostream>

namespace splat {

// Writes `codes` (8- or 16-bit per `bits`, interleaved, `channels` 1–4: grey, grey + alpha,
// RGB, RGBA; alpha straight) as a PNG to `out` (the caller's file: write_stream_atomically).
// Errors are InputError naming `file`: "cannot write image: ...".
void write_png_codes(const std::filesystem::path& file, std::ostream& out, int width, int height, int channels,
                     int bits, const void* codes);

}  // namespace splat
