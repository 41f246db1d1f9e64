#include "splat/data/undistort.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

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

// Whether the centre of pinhole pixel (i, j) maps inside the distorted photo (the test of
// sample_bilinear), for every pixel, row by row.
std::vector<std::uint8_t> covered_pixels(const Camera& pinhole, const LensDistortion& distortion) {
  const double fx = pinhole.fx, fy = pinhole.fy, cx = pinhole.cx, cy = pinhole.cy;
  std::vector<std::uint8_t> covered(std::size_t(pinhole.width) * std::size_t(pinhole.height));
  for (int j = 0; j < pinhole.height; ++j)
    for (int i = 0; i < pinhole.width; ++i) {
      double xd, yd;
      distortion.distort((i + 0.5 - cx) / fx, (j + 0.5 - cy) / fy, xd, yd);
      const double px = fx * xd + cx, py = fy * yd + cy;
      covered[std::size_t(j) * pinhole.width + i] =
          px >= 0 && px <= pinhole.width && py >= 0 && py <= pinhole.height;
    }
  return covered;
}

}  // namespace

PixelRect covered_region(const Camera& pinhole, const LensDistortion& distortion) {
  const std::vector<std::uint8_t> covered = covered_pixels(pinhole, distortion);
  int x0 = 0, y0 = 0, x1 = pinhole.width, y1 = pinhole.height;  // [x0, x1) x [y0, y1)
  auto uncovered_in_row = [&](int j) {
    int n = 0;
    for (int i = x0; i < x1; ++i) n += !covered[std::size_t(j) * pinhole.width + i];
    return n;
  };
  auto uncovered_in_column = [&](int i) {
    int n = 0;
    for (int j = y0; j < y1; ++j) n += !covered[std::size_t(j) * pinhole.width + i];
    return n;
  };
  while (x0 < x1 && y0 < y1) {
    // Sides in a fixed order (top, bottom, left, right); ties go to the first.
    const int counts[4] = {uncovered_in_row(y0), uncovered_in_row(y1 - 1), uncovered_in_column(x0),
                           uncovered_in_column(x1 - 1)};
    const int side = int(std::max_element(counts, counts + 4) - counts);
    if (counts[side] == 0) break;
    if (side == 0) ++y0;
    else if (side == 1) --y1;
    else if (side == 2) ++x0;
    else --x1;
  }
  if (x0 >= x1 || y0 >= y1) return {};
  return {x0, y0, x1 - x0, y1 - y0};
}

Camera crop_camera(const Camera& camera, const PixelRect& region) {
  Camera cropped = camera;
  cropped.cx -= float(region.x0);
  cropped.cy -= float(region.y0);
  cropped.width = region.width;
  cropped.height = region.height;
  return cropped;
}

Image crop_image(const Image& image, const PixelRect& region) {
  if (region.x0 < 0 || region.y0 < 0 || region.width < 0 || region.height < 0 ||
      region.x0 + region.width > image.width || region.y0 + region.height > image.height)
    throw ArgumentError("crop_image: region outside the " + std::to_string(image.width) + " x " +
                        std::to_string(image.height) + " image");
  Image out(region.width, region.height, image.channels);
  const std::size_t row_values = std::size_t(region.width) * image.channels;
  for (int j = 0; j < region.height; ++j)
    std::copy_n(image.data.begin() +
                    std::ptrdiff_t((std::size_t(region.y0 + j) * image.width + region.x0) * image.channels),
                row_values, &out.at(0, j, 0));
  return out;
}

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
