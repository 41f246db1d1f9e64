#include "splat/data/undistort.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "splat/core/error.hpp"

namespace splat {
namespace {

constexpr float kBlack[3] = {0, 0, 0};
constexpr float kMagenta[3] = {1, 0, 1};

Camera small_camera() {
  Camera cam;
  cam.width = 64, cam.height = 48;
  cam.fx = 50, cam.fy = 47;
  cam.cx = 32.3f, cam.cy = 23.7f;  // off-centre, as calibrated cameras are
  return cam;
}

// A smooth colour field over normalised camera coordinates: what a pinhole camera sees.
void field(double x, double y, float* rgb) {
  rgb[0] = float(0.5 + 0.4 * std::sin(3 * x + 1));
  rgb[1] = float(0.5 + 0.4 * std::cos(2 * y - 0.5));
  rgb[2] = float(0.5 + 0.3 * std::sin(2 * x + 2 * y));
}

Image pinhole_render(const Camera& cam) {
  Image image(cam.width, cam.height, 3);
  for (int j = 0; j < cam.height; ++j)
    for (int i = 0; i < cam.width; ++i)
      field((i + 0.5 - cam.cx) / cam.fx, (j + 0.5 - cam.cy) / cam.fy, &image.at(i, j, 0));
  return image;
}

// What the distorting lens records: the distorted pixel at normalised (xd, yd) sees the
// field where the forward model sends a point onto (xd, yd), found by Newton's method
// with a numerical Jacobian (independent of the code under test).
Image distorted_render(const Camera& cam, const LensDistortion& d) {
  Image image(cam.width, cam.height, 3);
  for (int j = 0; j < cam.height; ++j)
    for (int i = 0; i < cam.width; ++i) {
      const double xd = (i + 0.5 - cam.cx) / cam.fx, yd = (j + 0.5 - cam.cy) / cam.fy;
      double x = xd, y = yd;
      for (int iteration = 0; iteration < 30; ++iteration) {
        double fx0, fy0, fx1, fy1, fx2, fy2;
        const double h = 1e-7;
        d.distort(x, y, fx0, fy0);
        d.distort(x + h, y, fx1, fy1);
        d.distort(x, y + h, fx2, fy2);
        const double a = (fx1 - fx0) / h, b = (fx2 - fx0) / h;
        const double c = (fy1 - fy0) / h, e = (fy2 - fy0) / h;
        const double rx = fx0 - xd, ry = fy0 - yd, det = a * e - b * c;
        x -= (e * rx - b * ry) / det;
        y -= (a * ry - c * rx) / det;
      }
      double check_x, check_y;
      d.distort(x, y, check_x, check_y);
      EXPECT_NEAR(check_x, xd, 1e-10);
      EXPECT_NEAR(check_y, yd, 1e-10);
      field(x, y, &image.at(i, j, 0));
    }
  return image;
}

// PSNR over pixels whose distorted position lies at least `margin` pixels inside the image,
// where bilinear sampling has both neighbours.
double interior_psnr(const Image& a, const Image& b, const Camera& cam, const LensDistortion& d,
                     double margin) {
  double sum = 0;
  int count = 0;
  for (int j = 0; j < cam.height; ++j)
    for (int i = 0; i < cam.width; ++i) {
      double xd, yd;
      d.distort((i + 0.5 - cam.cx) / cam.fx, (j + 0.5 - cam.cy) / cam.fy, xd, yd);
      const double px = cam.fx * xd + cam.cx, py = cam.fy * yd + cam.cy;
      if (px < margin || py < margin || px > cam.width - margin || py > cam.height - margin)
        continue;
      for (int c = 0; c < 3; ++c) {
        const double diff = a.at(i, j, c) - b.at(i, j, c);
        sum += diff * diff;
      }
      ++count;
    }
  EXPECT_GT(count, cam.width * cam.height / 2);
  return -10 * std::log10(sum / (3.0 * count));
}

TEST(DatasetUndistort, ZeroDistortionIsTheIdentity) {
  const Camera cam = small_camera();
  Image image(cam.width, cam.height, 3);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0, 1);
  for (float& v : image.data) v = u(rng);
  const Image out = undistort_image(image, cam, LensDistortion{}, kMagenta);
  EXPECT_EQ(out.width, image.width);
  EXPECT_EQ(out.height, image.height);
  EXPECT_EQ(out.data, image.data);
}

TEST(DatasetUndistort, RecoversThePinholeImageForEachModel) {
  const Camera cam = small_camera();
  const Image expected = pinhole_render(cam);
  const LensDistortion models[] = {
      {-0.15, 0, 0, 0},            // SIMPLE_RADIAL, barrel
      {0.15, -0.05, 0, 0},         // RADIAL, pincushion
      {-0.12, 0.05, 0.01, -0.008}, // OPENCV
  };
  for (const LensDistortion& d : models) {
    const Image distorted = distorted_render(cam, d);
    const Image out = undistort_image(distorted, cam, d, kBlack);
    const double psnr = interior_psnr(out, expected, cam, d, 1.0);
    EXPECT_GT(psnr, 70.0) << "k1 " << d.k1;
    // The test can tell the model's direction: undistorting with the opposite coefficients
    // (roughly the inverse) or not at all is far worse.
    const LensDistortion opposite{-d.k1, -d.k2, -d.p1, -d.p2};
    const Image wrong = undistort_image(distorted, cam, opposite, kBlack);
    EXPECT_LT(interior_psnr(wrong, expected, cam, d, 1.0), psnr - 30) << "k1 " << d.k1;
    EXPECT_LT(interior_psnr(distorted, expected, cam, d, 1.0), psnr - 30) << "k1 " << d.k1;
  }
}

TEST(DatasetUndistort, PointsBeyondTheImageGetTheBackground) {
  const Camera cam = small_camera();
  const LensDistortion pincushion{0.5, 0, 0, 0};
  Image image(cam.width, cam.height, 3, 0.25f);
  const Image out = undistort_image(image, cam, pincushion, kMagenta);
  // The corner looks past the edge of the distorted photo; the centre does not.
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(out.at(0, 0, c), kMagenta[c]);
    EXPECT_EQ(out.at(cam.width - 1, cam.height - 1, c), kMagenta[c]);
    EXPECT_FLOAT_EQ(out.at(cam.width / 2, cam.height / 2, c), 0.25f);
  }
}

TEST(DatasetUndistort, CoveredRegionIsTheWholeImageForAPinhole) {
  const Camera cam = small_camera();
  const PixelRect r = covered_region(cam, LensDistortion{});
  EXPECT_EQ(r.x0, 0);
  EXPECT_EQ(r.y0, 0);
  EXPECT_EQ(r.width, cam.width);
  EXPECT_EQ(r.height, cam.height);
}

TEST(DatasetUndistort, CoveredRegionHoldsNoBackgroundAndLittleElse) {
  const Camera cam = small_camera();
  const LensDistortion lenses[] = {{0.15, -0.05, 0, 0}, {-0.12, 0.05, 0.01, -0.008}, {0.05, 0, 0.004, 0.002}};
  for (const LensDistortion& d : lenses) {
    const PixelRect r = covered_region(cam, d);
    ASSERT_GT(r.width, 0);
    ASSERT_GT(r.height, 0);
    // Not one pixel of the region shows the background...
    const Image out = undistort_image(Image(cam.width, cam.height, 3, 0.25f), cam, d, kMagenta);
    const Image region = crop_image(out, r);
    for (float v : region.data) ASSERT_EQ(v, 0.25f) << "k1 " << d.k1;
    // ...and each side stops at the image's edge or next to a row or column with background
    // (the greedy cut may overshoot by a little where two sides compete, never by much).
    auto has_background_row = [&](int j) {
      for (int i = r.x0; i < r.x0 + r.width; ++i)
        if (out.at(i, j, 1) == kMagenta[1]) return true;
      return false;
    };
    auto has_background_column = [&](int i) {
      for (int j = r.y0; j < r.y0 + r.height; ++j)
        if (out.at(i, j, 1) == kMagenta[1]) return true;
      return false;
    };
    int slack = 0;  // sides that could grow by a pixel without background
    slack += r.y0 > 0 && !has_background_row(r.y0 - 1);
    slack += r.y0 + r.height < cam.height && !has_background_row(r.y0 + r.height);
    slack += r.x0 > 0 && !has_background_column(r.x0 - 1);
    slack += r.x0 + r.width < cam.width && !has_background_column(r.x0 + r.width);
    EXPECT_LE(slack, 2) << "k1 " << d.k1;
    // The background in the full image is only a border band: most of the image stays.
    EXPECT_GT(double(r.width) * r.height, 0.6 * cam.width * cam.height) << "k1 " << d.k1;
  }
  // A lens that covers nothing of the pinhole image leaves an empty region.
  const PixelRect none = covered_region(cam, LensDistortion{1e6, 0, 0, 0});
  EXPECT_EQ(none.width * none.height, 0);
}

TEST(DatasetUndistort, CroppedCameraSeesTheCroppedPixels) {
  const Camera cam = small_camera();
  const PixelRect r{5, 3, 40, 30};
  const Camera cropped = crop_camera(cam, r);
  EXPECT_EQ(cropped.width, 40);
  EXPECT_EQ(cropped.height, 30);
  EXPECT_EQ(cropped.fx, cam.fx);
  // The field a pinhole sees through the cropped camera is the crop of the full view.
  const Image full = pinhole_render(cam), part = pinhole_render(cropped);
  const Image cut = crop_image(full, r);
  ASSERT_EQ(cut.width, part.width);
  for (std::size_t k = 0; k < cut.data.size(); ++k) EXPECT_NEAR(cut.data[k], part.data[k], 1e-5) << k;
  EXPECT_THROW(crop_image(full, PixelRect{30, 0, 40, 10}), ArgumentError);
}

TEST(DatasetUndistort, RejectsMismatchedImages) {
  const Camera cam = small_camera();
  EXPECT_THROW(undistort_image(Image(cam.width + 1, cam.height, 3), cam, {}, kBlack),
               ArgumentError);
  EXPECT_THROW(undistort_image(Image(cam.width, cam.height, 4), cam, {}, kBlack), ArgumentError);
}

}  // namespace
}  // namespace splat
