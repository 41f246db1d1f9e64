#include "splat/eval/half_fitted_psnr.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "splat/core/error.hpp"
#include "splat/eval/metrics.hpp"

namespace splat {
namespace {

// A photo with structure in every channel, different on the two halves.
Image textured_photo(int width, int height) {
  Image photo(width, height, 3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c)
        photo.at(x, y, c) = 0.2f + 0.6f * float(((x * 7 + y * 3 + c * 5) % 11)) / 10.0f;
  return photo;
}

TEST(HalfFittedPsnr, AnExposureChangeIsForgivenEntirely) {
  const Image photo = textured_photo(16, 9);
  Image render = photo;  // the same scene under other light: per-channel gain and offset
  const float gain[3] = {0.5f, 1.2f, 0.8f}, offset[3] = {0.1f, -0.1f, 0.05f};
  for (int y = 0; y < 9; ++y)
    for (int x = 0; x < 16; ++x)
      for (int c = 0; c < 3; ++c) render.at(x, y, c) = (photo.at(x, y, c) - offset[c]) / gain[c];
  EXPECT_LT(psnr(render, photo), 25.0);
  EXPECT_GT(half_fitted_psnr(render, photo), 100.0);
}

TEST(HalfFittedPsnr, ScoresTheRightHalfWithAFitFromTheLeft) {
  const Image photo = textured_photo(10, 4);
  Image render = photo;
  // An error on the left half is not scored (the fit still finds gain 1, offset 0 there:
  // one pixel off on an otherwise exact half moves them a little, so compare loosely).
  Image left_error = render;
  left_error.at(0, 0, 0) += 0.001f;
  EXPECT_GT(half_fitted_psnr(left_error, photo), 60.0);
  // An error on the right half is scored over the right half's samples alone.
  Image right_error = render;
  right_error.at(7, 2, 1) += 0.1f;
  const double expected = -10.0 * std::log10(0.1 * 0.1 / (5 * 4 * 3));
  EXPECT_NEAR(half_fitted_psnr(right_error, photo), expected, 1e-3);
}

TEST(HalfFittedPsnr, RefusesImagesWithoutTwoHalves) {
  EXPECT_THROW(half_fitted_psnr(Image(1, 4, 3), Image(1, 4, 3)), ArgumentError);
  EXPECT_THROW(half_fitted_psnr(Image(4, 4, 3), Image(4, 5, 3)), ArgumentError);
}

}  // namespace
}  // namespace splat
