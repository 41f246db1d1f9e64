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

// "" when width x height has sides of 1..kMaxImageSide and at most `max_pixels` pixels, else
// what is wrong with it (`what` names the thing: "an image").
inline std::string size_problem(long long width, long long height, std::size_t max_pixels, const char* what) {
  if (width < 1 || height < 1 || width > kMaxImageSide || height > kMaxImageSide)
    return "each side must be from 1 to " + std::to_string(kMaxImageSide) + " pixels";
  if (std::size_t(width) * std::size_t(height) > max_pixels)
    return "more than the " + std::to_string(max_pixels) + " pixels " + what + " may have";
  return "";
}

// "" when width x height is a size we read or write, else what is wrong with it.
inline std::string image_size_problem(long long width, long long height) {
  return size_problem(width, height, kMaxImagePixels, "an image");
}

// A camera may describe a photograph larger than the pixel limit (phones take 50 MP): its
// images then load reduced with a downscale (splat/data/image_io.hpp read_image_reduced).
constexpr std::size_t kMaxCameraPixels = std::size_t(1) << 28;

// "" when a camera of width x height is one we accept, else what is wrong with it.
inline std::string camera_size_problem(long long width, long long height) {
  return size_problem(width, height, kMaxCameraPixels, "a camera");
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
  bool empty() const { return data.empty(); }
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
