#include "splat/data/resample.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "splat/core/error.hpp"

namespace splat {
namespace {

// Which input samples along one axis feed each output sample, and with what weight.
struct AxisWeights {
  std::vector<int> first;       // [new_size + 1]: output o uses taps first[o] .. first[o+1]-1
  std::vector<int> index;       // [taps] input sample
  std::vector<float> weight;    // [taps] fraction of the output footprint it covers
};

AxisWeights area_weights(int old_size, int new_size) {
  AxisWeights w;
  w.first.reserve(std::size_t(new_size) + 1);
  const double scale = double(old_size) / double(new_size);  // input pixels per output pixel
  for (int o = 0; o < new_size; ++o) {
    w.first.push_back(int(w.index.size()));
    const double lo = o * scale, hi = (o + 1) * scale;
    const int begin = int(std::floor(lo));
    const int end = std::min(old_size, int(std::ceil(hi)));
    for (int i = begin; i < end; ++i) {
      const double covered = std::min(hi, double(i + 1)) - std::max(lo, double(i));
      // Footprint edges that land on a pixel edge up to rounding leave slivers of ~1e-16.
      if (covered <= 1e-12) continue;
      w.index.push_back(i);
      w.weight.push_back(float(covered / scale));
    }
  }
  w.first.push_back(int(w.index.size()));
  return w;
}

}  // namespace

Image resample_area(const Image& image, int new_width, int new_height) {
  if (new_width < 1 || new_height < 1 || image.width < 1 || image.height < 1 ||
      image.channels < 1 ||
      image.data.size() != image.pixel_count() * std::size_t(image.channels))
    throw ArgumentError("resample_area: cannot resample a " + std::to_string(image.width) +
                        " x " + std::to_string(image.height) + " x " +
                        std::to_string(image.channels) + " image to " +
                        std::to_string(new_width) + " x " + std::to_string(new_height));
  if (new_width == image.width && new_height == image.height) return image;

  const int channels = image.channels;
  const AxisWeights wx = area_weights(image.width, new_width);
  const AxisWeights wy = area_weights(image.height, new_height);

  // Separable: rows first (every input row to the new width), then columns.
  Image rows(new_width, image.height, channels);
  tbb::parallel_for(tbb::blocked_range<int>(0, image.height), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y != r.end(); ++y)
      for (int o = 0; o < new_width; ++o)
        for (int c = 0; c < channels; ++c) {
          float sum = 0;
          for (int t = wx.first[o]; t < wx.first[o + 1]; ++t)
            sum += wx.weight[t] * image.at(wx.index[t], y, c);
          rows.at(o, y, c) = sum;
        }
  });
  Image out(new_width, new_height, channels);
  tbb::parallel_for(tbb::blocked_range<int>(0, new_height), [&](const tbb::blocked_range<int>& r) {
    for (int o = r.begin(); o != r.end(); ++o)
      for (int x = 0; x < new_width; ++x)
        for (int c = 0; c < channels; ++c) {
          float sum = 0;
          for (int t = wy.first[o]; t < wy.first[o + 1]; ++t)
            sum += wy.weight[t] * rows.at(x, wy.index[t], c);
          out.at(x, o, c) = sum;
        }
  });
  return out;
}

}  // namespace splat
