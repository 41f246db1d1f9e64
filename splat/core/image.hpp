#pragma once
// A float image, interleaved channels, row-major: data[(y * width + x) * channels + c].
#include <cstddef>
#include <string>
#include <vector>

namespace splat {

// Limits of every image read or written (docs/DESIGN.md §4.4): a larger header is taken as
// corrupt rather than an allocation to attempt. At the pixel limit an RGBA float image takes
// 256 MB, so a tool holding two of them with their decoding buffers stays within 1 GB
// (splat-psnr on two RGBA images at the limit peaked at 2.7 GB when the limit was 2^26).
constexpr int kMaxImageSide = 1 << 16;
constexpr std::size_t kMaxImagePixels = std::size_t(1) << 24;  // 4,096 × 4,096

// "" when width x height is a size we read or write, else what is wrong with it.
inline std::string image_size_problem(long long width, long long height) {
  if (width < 1 || height < 1 || width > kMaxImageSide || height > kMaxImageSide)
    return "each side must be from 1 to " + std::to_string(kMaxImageSide) + " pixels";
  if (std::size_t(width) * std::size_t(height) > kMaxImagePixels)
    return "more than the " + std::to_string(kMaxImagePixels) + " pixels an image may have";
  return "";
}

// An image file's size and channel count, read from its header.
struct ImageInfo {
  int width = 0, height = 0, channels = 0;
};

struct Image {
  int width = 0, height = 0, channels = 0;
  std::vector<float> data;  // [height, width, channels]

  Image() = default;
  Image(int w, int h, int c, float fill = 0.0f)
      : width(w), height(h), channels(c), data(std::size_t(w) * h * c, fill) {}
  float& at(int x, int y, int c) { return data[(std::size_t(y) * width + x) * channels + c]; }
  float at(int x, int y, int c) const { return data[(std::size_t(y) * width + x) * channels + c]; }
  std::size_t pixel_count() const { return std::size_t(width) * height; }
};

// An RGBA image with straight (unpremultiplied) alpha, as PNG stores it, seen over a
// background: rgb·a + bg·(1 − a). Datasets and image comparisons both need exactly this.
inline Image composite_onto(const Image& rgba, const float background[3]) {
  Image rgb(rgba.width, rgba.height, 3);
  for (std::size_t p = 0; p < rgba.pixel_count(); ++p) {
    const float* in = &rgba.data[p * 4];
    const float alpha = in[3];
    for (int c = 0; c < 3; ++c) rgb.data[p * 3 + c] = in[c] * alpha + background[c] * (1.0f - alpha);
  }
  return rgb;
}

}  // namespace splat
