// Conformance with the official CUDA rasterizer (testdata/conformance/README.md): our renders of the
// shared 50k-Gaussian lego model must reach PSNR >= 45 dB against its images, every view.
#include <gtest/gtest.h>

#include <algorithm>

#include "splat/data/image_io.hpp"
#include "splat/data/transforms_json.hpp"
#include "splat/gaussians/ply_io.hpp"
#include "splat/raster/rasterizer.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

constexpr double kConformancePsnrDb = 45.0;

TEST(Conformance, EveryReferenceViewAbove45Db) {
  const auto dir = test::conformance_dir();
  const auto [model, frames] = test::load_conformance(400);
  ASSERT_EQ(frames.size(), 13u);

  Rasterizer rasterizer;
  RenderResult result;
  RenderSettings settings;  // white background, all SH bands
  for (const CameraFrame& frame : frames) {
    rasterizer.render(model, frame.camera, settings, result);
    Image ours = result.color;
    for (float& v : ours.data) v = std::clamp(v, 0.0f, 1.0f);  // as the reference script does
    const Image reference = read_image(dir / "reference" / (frame.name + ".png"));
    ASSERT_EQ(reference.channels, 3);
    const double db = psnr(ours, reference);
    EXPECT_GE(db, kConformancePsnrDb) << frame.name;
    std::printf("conformance %s: %.2f dB\n", frame.name.c_str(), db);
  }
}

}  // namespace
}  // namespace splat
