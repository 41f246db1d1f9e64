#include "splat/eval/half_fitted_psnr.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "splat/core/error.hpp"

namespace splat {

double half_fitted_psnr(const Image& render, const Image& photo) {
  if (render.width != photo.width || render.height != photo.height || render.channels != photo.channels)
    throw ArgumentError("half_fitted_psnr: images differ in shape");
  if (render.width < 2 || render.height < 1 || render.channels < 1)
    throw ArgumentError("half_fitted_psnr: an image " + std::to_string(render.width) +
                        " pixels wide has no two halves");
  const int split = render.width / 2;
  double squared_error = 0;
  std::size_t samples = 0;
  for (int c = 0; c < render.channels; ++c) {
    // Least squares photo ≈ gain·render + offset over the left half.
    double n = 0, sum_r = 0, sum_p = 0, sum_rr = 0, sum_rp = 0;
    for (int y = 0; y < render.height; ++y)
      for (int x = 0; x < split; ++x) {
        const double r = render.at(x, y, c), p = photo.at(x, y, c);
        n += 1;
        sum_r += r;
        sum_p += p;
        sum_rr += r * r;
        sum_rp += r * p;
      }
    const double variance = sum_rr - sum_r * sum_r / n;
    // A flat left half fixes no gain: keep the render's contrast and match the mean.
    const double gain = variance > 1e-12 * n ? (sum_rp - sum_r * sum_p / n) / variance : 1.0;
    const double offset = (sum_p - gain * sum_r) / n;
    for (int y = 0; y < render.height; ++y)
      for (int x = split; x < render.width; ++x) {
        const double mapped = std::clamp(gain * render.at(x, y, c) + offset, 0.0, 1.0);
        const double d = mapped - double(photo.at(x, y, c));
        squared_error += d * d;
        ++samples;
      }
  }
  if (squared_error == 0) return std::numeric_limits<double>::infinity();
  return -10.0 * std::log10(squared_error / double(samples));
}

}  // namespace splat
