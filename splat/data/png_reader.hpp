#pragma once
// PNG files read with libpng directly. OpenImageIO reads every other format, but its PNG
// reader lets libpng print "libpng error: ..." on stderr before returning, and reports one
// failure as three lines; here libpng's errors and warnings come back to us alone, so a
// damaged PNG is one line naming the file, and nothing else reaches the terminal.
#include <filesystem>

#include "splat/core/image.hpp"

namespace splat {

// The header (channels after expansion: palette to RGB, tRNS to alpha), checked against the image limits (image.hpp) and against the file's size: a
// header claiming more pixels than its bytes could hold is refused before anything is
// allocated. Throws InputError naming the file.
ImageInfo read_png_header(const std::filesystem::path& file);

// The pixels as float in [0, 1]: code × (1 / max code), the conversion OpenImageIO makes, so
// every reader gives the same values. Palette images become RGB(A), low bit depths 8-bit
// codes, and a tRNS chunk an alpha channel; alpha stays straight; no gamma is applied.
Image read_png(const std::filesystem::path& file);

}  // namespace splat
