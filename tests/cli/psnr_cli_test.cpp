// splat-psnr: a dataset's RGBA test image compared with a render over the same background
// (--bg composites it first), and a clear error for a missing counterpart.
#include <gtest/gtest.h>

#include "tests/cli_support.hpp"
#include "splat/data/image_io.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

TEST(PsnrCli, CompositesRgbaOntoTheBackgroundWhenAsked) {
  const fs::path dir = test::scratch_dir("psnr_cli");
  // Half the pixels transparent (any colour), half opaque mid-grey: over white that is the
  // render below exactly; without compositing, the transparent half's colour counts.
  Image rgba(8, 8, 4), render(8, 8, 3);
  for (std::size_t p = 0; p < rgba.pixel_count(); ++p) {
    const bool opaque = p % 2 == 0;
    for (int c = 0; c < 3; ++c) {
      rgba.data[4 * p + c] = opaque ? 0.4f : 0.0f;
      render.data[3 * p + c] = opaque ? 0.4f : 1.0f;
    }
    rgba.data[4 * p + 3] = opaque ? 1.0f : 0.0f;
  }
  write_png(rgba, dir / "truth.png", 16);
  write_png(render, dir / "render.png", 16);
  const std::string exe = SPLAT_PSNR_EXE;
  const auto composited = test::run_command(exe + " " + (dir / "render.png").string() + " " +
                                                (dir / "truth.png").string() + " --bg 1,1,1", dir);
  ASSERT_EQ(composited.exit_code, 0) << composited.err;
  EXPECT_GT(std::stod(composited.out), 90.0) << composited.out;  // equal up to 16-bit rounding
  const auto raw = test::run_command(exe + " " + (dir / "render.png").string() + " " +
                                         (dir / "truth.png").string(), dir);
  ASSERT_EQ(raw.exit_code, 0) << raw.err;
  EXPECT_LT(std::stod(raw.out), 10.0) << raw.out;  // half the pixels off by 1.0: 3 dB

  const auto missing = test::run_command(exe + " " + dir.string() + " " + (dir / "nowhere").string(), dir);
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("nowhere"), std::string::npos) << missing.err;
}

}  // namespace
}  // namespace splat
