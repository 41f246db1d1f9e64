#include "splat/data/resample.hpp"

#include <gtest/gtest.h>

#include <random>

#include "splat/core/error.hpp"

namespace splat {
namespace {

Image random_image(int width, int height, int channels, unsigned seed) {
  Image image(width, height, channels);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0, 1);
  for (float& v : image.data) v = u(rng);
  return image;
}

// Exact area average by counting cells: scaled by the new size along each axis, input pixel
// i covers cells [i·new, (i+1)·new) and output pixel o covers [o·old, (o+1)·old), so every
// unit cell lies in exactly one of each.
Image cell_reference(const Image& in, int new_width, int new_height) {
  Image out(new_width, new_height, in.channels);
  for (int oy = 0; oy < new_height; ++oy)
    for (int ox = 0; ox < new_width; ++ox)
      for (int c = 0; c < in.channels; ++c) {
        double sum = 0;
        int cells = 0;
        for (int ky = oy * in.height; ky < (oy + 1) * in.height; ++ky)
          for (int kx = ox * in.width; kx < (ox + 1) * in.width; ++kx) {
            sum += in.at(kx / new_width, ky / new_height, c);
            ++cells;
          }
        out.at(ox, oy, c) = float(sum / cells);
      }
  return out;
}

TEST(DatasetResample, IntegerFactorAveragesBlocks) {
  const Image in = random_image(6, 4, 3, 1);
  const Image out = resample_area(in, 3, 2);
  ASSERT_EQ(out.width, 3);
  ASSERT_EQ(out.height, 2);
  ASSERT_EQ(out.channels, 3);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x)
      for (int c = 0; c < 3; ++c) {
        const float mean = (in.at(2 * x, 2 * y, c) + in.at(2 * x + 1, 2 * y, c) +
                            in.at(2 * x, 2 * y + 1, c) + in.at(2 * x + 1, 2 * y + 1, c)) / 4;
        EXPECT_NEAR(out.at(x, y, c), mean, 1e-6f);
      }
}

TEST(DatasetResample, FractionalFootprintsMatchExactAreas) {
  // 7 x 5 by 2: floor gives 3 x 2, so each output pixel covers 7/3 x 5/2 input pixels.
  const Image in = random_image(7, 5, 4, 2);
  const Image out = resample_area(in, 3, 2);
  const Image expected = cell_reference(in, 3, 2);
  ASSERT_EQ(out.data.size(), expected.data.size());
  for (std::size_t i = 0; i < out.data.size(); ++i) EXPECT_NEAR(out.data[i], expected.data[i], 1e-6f);
}

TEST(DatasetResample, ConstantStaysConstantAndSameSizeIsACopy) {
  const Image grey(11, 9, 3, 0.4f);
  for (float v : resample_area(grey, 3, 4).data) EXPECT_NEAR(v, 0.4f, 1e-6f);
  const Image in = random_image(5, 3, 3, 3);
  EXPECT_EQ(resample_area(in, 5, 3).data, in.data);
}

TEST(DatasetResample, RejectsEmptySizes) {
  EXPECT_THROW(resample_area(Image(4, 4, 3), 0, 2), ArgumentError);
  EXPECT_THROW(resample_area(Image(), 2, 2), ArgumentError);
}

}  // namespace
}  // namespace splat
