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

}  // namespace splat
