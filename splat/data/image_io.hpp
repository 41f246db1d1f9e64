#pragma once
// Image files through OpenImageIO.
#include <filesystem>

#include "splat/core/image.hpp"

namespace splat {

// Reads any format OpenImageIO knows, as float in [0, 1] for integer formats, keeping the
// file's channel count. Throws InputError naming the file when it cannot be read.
Image read_image(const std::filesystem::path& file);

// Writes a PNG with values clamped to [0, 1] and quantised to `bits` (8 or 16) per channel,
// through a temporary file renamed into place. Throws Error naming the file on failure.
void write_png(const Image& image, const std::filesystem::path& file, int bits = 8);

// Writes raw float data (e.g. EXR) without clamping, through a temporary file.
void write_float_image(const Image& image, const std::filesystem::path& file);

}  // namespace splat
