#include "splat/eval/metrics.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "splat/core/error.hpp"

namespace splat {

namespace {

std::string shape(const Image& i) {
  return std::to_string(i.width) + "x" + std::to_string(i.height) + "x" + std::to_string(i.channels);
}

void check_same_shape(const char* what, const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels)
    throw ArgumentError(std::string(what) + ": images differ in shape (" + shape(a) + " vs " + shape(b) + ")");
}

void check_mask(const char* what, const Image& image, const Image& mask) {
  if (mask.width != image.width || mask.height != image.height || mask.channels != 1)
    throw ArgumentError(std::string(what) + ": the mask is " + shape(mask) + ", not " +
                        std::to_string(image.width) + "x" + std::to_string(image.height) + "x1");
}

}  // namespace

double masked_psnr(const Image& a, const Image& b, const Image& mask) {
  check_same_shape("masked_psnr", a, b);
  check_mask("masked_psnr", a, mask);
  const std::size_t channels = std::size_t(a.channels);
  double sum = 0, kept = 0;
  for (std::size_t p = 0; p < a.pixel_count(); ++p) {
    kept += mask.data[p];
    for (std::size_t c = 0; c < channels; ++c) {
      const double d = double(a.data[p * channels + c]) - double(b.data[p * channels + c]);
      sum += double(mask.data[p]) * d * d;
    }
  }
  if (!(kept > 0) || sum == 0) return std::numeric_limits<double>::infinity();
  return -10.0 * std::log10(sum / (kept * double(channels)));
}

Image masked(const Image& image, const Image& mask) {
  check_mask("masked", image, mask);
  Image out = image;
  const std::size_t channels = std::size_t(image.channels);
  for (std::size_t p = 0; p < image.pixel_count(); ++p)
    for (std::size_t c = 0; c < channels; ++c) out.data[p * channels + c] *= mask.data[p];
  return out;
}

double psnr(const Image& a, const Image& b) {
  check_same_shape("psnr", a, b);
  double sum = 0;  // double: a 4-megapixel image's squared errors need the precision
  for (std::size_t i = 0; i < a.data.size(); ++i) {
    const double d = double(a.data[i]) - double(b.data[i]);
    sum += d * d;
  }
  if (a.data.empty() || sum == 0) return std::numeric_limits<double>::infinity();
  return -10.0 * std::log10(sum / double(a.data.size()));
}

}  // namespace splat
