#pragma once
// JPEG files read with libjpeg directly, for the reasons PNGs are (png_reader.hpp) and one
// more: OpenImageIO 2.4's JPEG reader parses IPTC metadata out of bounds on a damaged file
// (a heap-buffer-overflow the image fuzz target found). libjpeg here reads only the pixels;
// every marker we do not need is skipped unread.
#include <filesystem>

#include "splat/core/image.hpp"

namespace splat {

// The header (1 channel for grey, 3 for colour), checked against the image limits (image.hpp). InputError naming the file.
ImageInfo read_jpeg_header(const std::filesystem::path& file);

// The pixels as float: code × (1 / 255), as OpenImageIO gives them (libjpeg's default
// decoding). A file that ends early or has corrupt data is an error, not an image libjpeg
// padded with grey.
Image read_jpeg(const std::filesystem::path& file);

// The pixels decoded at 1/`denominator` of the stored size (1, 2, 4 or 8; libjpeg's DCT
// scaling, each side rounded up), so that a photograph larger than the pixel limit loads
// when its reduced size fits: only the reduced size is checked against the limits. Also the
// stored size (unchecked; read_jpeg_stored_size reads only that). ArgumentError for another
// denominator.
ImageInfo read_jpeg_stored_size(const std::filesystem::path& file);
struct ReducedJpeg {
  ImageInfo stored;
  Image image;
};
ReducedJpeg read_jpeg_reduced(const std::filesystem::path& file, unsigned denominator);

}  // namespace splat
