#include "splat/data/undistort.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "splat/core/error.hpp"

namespace splat {
namespace {

constexpr int kChannels = 3;

// Bilinear sample at continuous pixel coordinates (px, py), pixel i covering [i, i+1].
// Between the outermost pixel centres and the image edge the edge pixel is used as it is.
void sample_bilinear(const Image& image, double px, double py, const float background[3],
                     float* out) {
  if (!(px >= 0 && px <= image.width && py >= 0 && py <= image.height)) {
    for (int c = 0; c < kChannels; ++c) out[c] = background[c];
    return;
  }
  const double sx = std::clamp(px - 0.5, 0.0, double(image.width - 1));
  const double sy = std::clamp(py - 0.5, 0.0, double(image.height - 1));
  const int x0 = int(sx), y0 = int(sy);  // sx, sy >= 0, so truncation is floor
  const int x1 = std::min(x0 + 1, image.width - 1), y1 = std::min(y0 + 1, image.height - 1);
  const double wx = sx - x0, wy = sy - y0;
  for (int c = 0; c < kChannels; ++c) {
    const double top = (1 - wx) * image.at(x0, y0, c) + wx * image.at(x1, y0, c);
    const double bottom = (1 - wx) * image.at(x0, y1, c) + wx * image.at(x1, y1, c);
    out[c] = float((1 - wy) * top + wy * bottom);
  }
}

}  // namespace

Image undistort_image(const Image& distorted, const Camera& pinhole,
                      const LensDistortion& distortion, const float background[3]) {
  if (distorted.channels != kChannels || distorted.width != pinhole.width ||
      distorted.height != pinhole.height ||
      distorted.data.size() != distorted.pixel_count() * kChannels)
    throw ArgumentError("undistort_image: expected a " + std::to_string(pinhole.width) + " x " +
                        std::to_string(pinhole.height) + " RGB image, got " +
                        std::to_string(distorted.width) + " x " +
                        std::to_string(distorted.height) + " x " +
                        std::to_string(distorted.channels));
  Image out(pinhole.width, pinhole.height, kChannels);
  // Double precision keeps the round trip pixel -> normalised -> pixel exact to far below a
  // float's resolution, so zero distortion reproduces the input.
  const double fx = pinhole.fx, fy = pinhole.fy, cx = pinhole.cx, cy = pinhole.cy;
  tbb::parallel_for(tbb::blocked_range<int>(0, out.height), [&](const tbb::blocked_range<int>& rows) {
    for (int j = rows.begin(); j != rows.end(); ++j) {
      const double y = (j + 0.5 - cy) / fy;
      for (int i = 0; i < out.width; ++i) {
        const double x = (i + 0.5 - cx) / fx;
        double xd, yd;
        distortion.distort(x, y, xd, yd);
        sample_bilinear(distorted, fx * xd + cx, fy * yd + cy, background, &out.at(i, j, 0));
      }
    }
  });
  return out;
}

}  // namespace splat
