#include "splat/eval/metrics.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "splat/core/error.hpp"

namespace splat {

double psnr(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels)
    throw ArgumentError("psnr: images differ in shape (" + std::to_string(a.width) + "x" +
                        std::to_string(a.height) + "x" + std::to_string(a.channels) + " vs " +
                        std::to_string(b.width) + "x" + std::to_string(b.height) + "x" +
                        std::to_string(b.channels) + ")");
  double sum = 0;  // double: a 4-megapixel image's squared errors need the precision
  for (std::size_t i = 0; i < a.data.size(); ++i) {
    const double d = double(a.data[i]) - double(b.data[i]);
    sum += d * d;
  }
  if (a.data.empty() || sum == 0) return std::numeric_limits<double>::infinity();
  return -10.0 * std::log10(sum / double(a.data.size()));
}

}  // namespace splat
