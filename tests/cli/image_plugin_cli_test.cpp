// OpenImageIO is a plugin loaded on first use (splat/data/oiio_plugin.hpp): no program links
// it, so none pays its ~260 libraries at start; PNGs are read and written without it; a
// format that needs it works where the plugin is and is refused, naming the image and the
// plugin, where it is not.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "splat/data/image_io.hpp"
#include "tests/cli_support.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

TEST(ImagePluginCli, NoProgramLinksOpenImageIo) {
  const fs::path dir = test::scratch_dir("image_plugin_links");
  for (const char* exe : {SPLAT_TRAIN_EXE, SPLAT_RENDER_EXE, SPLAT_EVAL_EXE, SPLAT_VIEWER_EXE, SPLAT_PSNR_EXE,
                          SPLAT_PROCESS_EXE, SPLAT_SCENE_EXE, SPLAT_CONVERT_EXE, SPLAT_GRAD_EXE, SPLAT_DEMO_EXE}) {
    // What the dynamic loader would load at start (ldd's way), without running the program.
    const auto r = test::run_command("LD_TRACE_LOADED_OBJECTS=1 " + std::string(exe), dir);
    ASSERT_EQ(r.exit_code, 0) << exe << "\n" << r.err;
    EXPECT_NE(r.out.find("libc.so"), std::string::npos) << exe << "\n" << r.out;  // the listing is there
    EXPECT_EQ(r.out.find("libOpenImageIO"), std::string::npos) << exe << "\n" << r.out;
  }
}

TEST(ImagePluginCli, PngNeedsNoPluginAndAMissingPluginIsNamedWithTheImage) {
  const fs::path dir = test::scratch_dir("image_plugin_missing");
  Image a(6, 4, 3, 0.25f), b(6, 4, 3, 0.25f);
  b.data[0] = 0.5f;
  write_png(a, dir / "a.png");
  write_png(b, dir / "b.png");
  write_float_image(a, dir / "a.exr");
  write_float_image(b, dir / "b.exr");
  // The program alone in a folder with no lib/splat/ beside it.
  fs::create_directories(dir / "bin");
  const fs::path alone = dir / "bin" / "splat-psnr";
  fs::copy_file(SPLAT_PSNR_EXE, alone, fs::copy_options::overwrite_existing);
  const auto png = test::run_command(alone.string() + " " + (dir / "a.png").string() + " " + (dir / "b.png").string(), dir);
  ASSERT_EQ(png.exit_code, 0) << png.err;
  EXPECT_GT(std::stod(png.out), 20.0) << png.out;

  const auto exr = test::run_command(alone.string() + " " + (dir / "a.exr").string() + " " + (dir / "b.exr").string(), dir);
  EXPECT_EQ(exr.exit_code, 2) << exr.err;
  EXPECT_NE(exr.err.find("a.exr"), std::string::npos) << exr.err;
  EXPECT_NE(exr.err.find("libsplat_oiio.so"), std::string::npos) << exr.err;
  EXPECT_EQ(exr.err.find('\n'), exr.err.size() - 1) << "one line: " << exr.err;
  // Where the build put it, the same program reads them.
  const auto found = test::run_command(std::string(SPLAT_PSNR_EXE) + " " + (dir / "a.exr").string() + " " +
                                           (dir / "b.exr").string(), dir);
  ASSERT_EQ(found.exit_code, 0) << found.err;
  EXPECT_NEAR(std::stod(found.out), 30.6, 0.1) << found.out;  // one value of 72 off by 0.25
}

}  // namespace
}  // namespace splat
