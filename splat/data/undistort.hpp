#pragma once
// Lens undistortion: resamples a photo taken through a distorting lens into the image an
// ideal pinhole camera with the same focal lengths, principal point and size would see.
#include "splat/core/camera.hpp"
#include "splat/core/image.hpp"

namespace splat {

// COLMAP's radial-tangential model on normalised camera coordinates (x, y) = (X/Z, Y/Z):
//   r² = x² + y²,  radial = k1 r² + k2 r⁴
//   x_d = x + x·radial + 2 p1 x y + p2 (r² + 2x²)
//   y_d = y + y·radial + p1 (r² + 2y²) + 2 p2 x y
// SIMPLE_RADIAL is k1 alone, RADIAL k1 and k2, OPENCV all four.
struct LensDistortion {
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0;

  bool is_identity() const { return k1 == 0 && k2 == 0 && p1 == 0 && p2 == 0; }
  // Undistorted normalised coordinates to distorted ones (the forward model above).
  void distort(double x, double y, double& x_distorted, double& y_distorted) const {
    const double x2 = x * x, y2 = y * y, xy = x * y, r2 = x2 + y2;
    const double radial = k1 * r2 + k2 * r2 * r2;
    x_distorted = x + x * radial + 2 * p1 * xy + p2 * (r2 + 2 * x2);
    y_distorted = y + y * radial + p1 * (r2 + 2 * y2) + 2 * p2 * xy;
  }
};

// The pinhole image for `pinhole` (whose size must equal `distorted`'s) from an image taken
// with the same intrinsics and `distortion`. Each output pixel centre (u, v) maps to
// normalised (x, y) = ((u - cx)/fx, (v - cy)/fy), through the forward model, and back to
// pixels in `distorted`, which is sampled bilinearly between pixel centres (i + 0.5); points
// beyond the image's edges [0, W] x [0, H] get `background`. Zero coefficients return the
// input unchanged up to float rounding. Three channels; parallel over rows, deterministic.
// Throws ArgumentError for mismatched sizes or channel counts.
Image undistort_image(const Image& distorted, const Camera& pinhole,
                      const LensDistortion& distortion, const float background[3]);

// Pixels [x0, x0 + width) x [y0, y0 + height) of an image.
struct PixelRect {
  int x0 = 0, y0 = 0, width = 0, height = 0;
};

// The part of `pinhole`'s image that the distorted photo covers: a rectangle in which every
// pixel centre maps inside the photo, so undistort_image fills none of it with the
// background. Found by cutting, one row or column at a time, the side with the most
// uncovered pixels until none is left (the full image when the lens covers it all). The
// border it removes holds no photograph: kept, it is a constant colour no view agrees on,
// which the model cannot learn and which the test views score against (a 3-pixel band cost
// real_thermos_distorted 10 dB). Empty when nothing is covered.
PixelRect covered_region(const Camera& pinhole, const LensDistortion& distortion);

// The camera that sees `region` of `camera`'s image: the same focal lengths, the principal
// point moved by the region's corner, the region's size.
Camera crop_camera(const Camera& camera, const PixelRect& region);
// `region` of `image` (which must contain it).
Image crop_image(const Image& image, const PixelRect& region);

}  // namespace splat
