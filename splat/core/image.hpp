#pragma once
// A float image, interleaved channels, row-major: data[(y * width + x) * channels + c].
#include <cstddef>
#include <vector>

namespace splat {

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
