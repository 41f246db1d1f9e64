#pragma once
// Image files: PNG and JPEG through libpng and libjpeg, the other formats through OpenImageIO.
#include <cstdint>
#include <filesystem>
#include <vector>

#include "splat/core/image.hpp"

namespace splat {

// Reads PNG, JPEG, TIFF, OpenEXR, BMP, WebP and Radiance HDR (told by the first bytes, not the name), as float in [0, 1] for integer formats, keeping the
// file's channel count. Values come back exactly as stored: alpha is not premultiplied into
// the colour (PNG stores straight alpha, and datasets composite it onto a background
// themselves). Throws InputError naming the file when it cannot be read.
Image read_image(const std::filesystem::path& file);

// The image at 1/`reduction` of its size (floor of each side), averaged over areas. A JPEG is
// decoded at the largest of 1/2, 1/4 or 1/8 not beyond the reduction by libjpeg, and only that
// size must fit the pixel limit: a 24 MP photograph loads at a half or less. Other formats are decoded
// whole first. InputError naming the file, also when a side would be 0; ArgumentError for a
// reduction below 1.
Image read_image_reduced(const std::filesystem::path& file, int reduction);

// Size and channel count from the file's header, without decoding pixels.
ImageInfo read_image_info(const std::filesystem::path& file);
// The same, for a JPEG without the pixel limit (what read_image_reduced may still load).
ImageInfo read_image_stored_size(const std::filesystem::path& file);

// Writes a PNG (whatever the extension) with values clamped to [0, 1] (NaN becomes 0) and
// rounded to `bits` (8 or 16) per channel, straight alpha, 1 to 4 channels, through a
// temporary file renamed into place. Throws InputError naming the file when writing fails,
// ArgumentError for an image or bit depth PNG cannot hold.
void write_png(const Image& image, const std::filesystem::path& file, int bits = 8);

// The 8-bit codes write_png stores for `image` (clamped, NaN as 0, rounded), interleaved as
// the image is: for writers of other formats (splat-render's video frames).
std::vector<std::uint8_t> image_codes_8bit(const Image& image);

// Writes float data without clamping, through a temporary file; the format follows the
// extension (e.g. .exr, .tif). Throws InputError naming the file when writing fails or the
// format cannot store 32-bit floats (e.g. .png).
void write_float_image(const Image& image, const std::filesystem::path& file);

}  // namespace splat
