// splat-viewer under Xvfb (Mesa's software OpenGL): its --screenshot of a view matches what
// splat-render makes of the same camera, for a splat model, for two models side by side
// (a NeRF among them, refined to full resolution), and bad input exits 2 without a window.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include <nlohmann/json.hpp>

#include "tests/cli_support.hpp"
#include "splat/data/image_io.hpp"
#include "splat/eval/metrics.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

std::string conformance(const std::string& name) { return (test::conformance_dir() / name).string(); }

// A virtual display per command. ctest runs tests in parallel, and two xvfb-run -a started
// at once can race for the same free server number, so each test searches from its own.
// In the sanitizer build, Mesa's software GL driver leaves a few allocations behind that
// LeakSanitizer cannot attribute (the driver is unloaded before the check, so its frames have
// no module to suppress by): leak checking is off for the windowed runs only; the rest of
// ASan and UBSan stays on, and the viewer's code without a window is leak-checked elsewhere.
std::string under_xvfb(const std::string& command, int first_server) {
  return "xvfb-run -a -n " + std::to_string(first_server) + " -s '-screen 0 1600x1200x24' " +
         "env ASAN_OPTIONS=\"${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0\" " + command;
}

Image crop(const Image& image, int x0, int width) {
  Image out(width, image.height, 3);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = image.at(x0 + x, y, c);
  return out;
}

// splat-render of `model` for view 0 of the conformance cameras at 200x200.
Image reference_render(const std::string& model, const fs::path& dir) {
  const auto r = test::run_command(std::string(SPLAT_RENDER_EXE) + " --model " + model + " --cameras " +
                                       conformance("transforms_test.json") + " --width 200 --height 200 --out " +
                                       (dir / "reference").string(),
                                   dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return read_image(dir / "reference" / "r_0.png");
}

TEST(ViewerCli, XvfbIsInstalled) {
  // The screenshot tests need it; scripts/install-deps.sh installs it.
  EXPECT_EQ(std::system("command -v xvfb-run > /dev/null"), 0) << "xvfb-run not found (install xvfb xauth)";
}

TEST(ViewerCli, ScreenshotOfAViewMatchesSplatRender) {
  const fs::path dir = test::scratch_dir("viewer_cli_screenshot");
  const fs::path shot = dir / "shot.png";
  const auto r = test::run_command(
      under_xvfb(std::string(SPLAT_VIEWER_EXE) + " " + conformance("lego_subset50k.ply") + " --cameras " +
                 conformance("transforms_test.json") + " --view 0 --width 200 --height 200 --screenshot " +
                 shot.string(), 121),
      dir);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const Image viewer = read_image(shot);
  ASSERT_EQ(viewer.width, 200);
  ASSERT_EQ(viewer.height, 200);
  EXPECT_GE(psnr(crop(viewer, 0, 200), reference_render(conformance("lego_subset50k.ply"), dir)), 40.0);
}

TEST(ViewerCli, AModelInATrainingFolderStartsAtItsFirstTrainingView) {
  // No --cameras: the cameras_train.json beside the model gives the views, as in a
  // splat-train output folder, so the first picture is its view 0.
  const fs::path dir = test::scratch_dir("viewer_cli_cameras_beside");
  fs::create_directories(dir / "run");
  fs::copy_file(conformance("lego_subset50k.ply"), dir / "run" / "model.ply");
  fs::copy_file(conformance("transforms_test.json"), dir / "run" / "cameras_train.json");
  const fs::path shot = dir / "shot.png";
  const auto r = test::run_command(under_xvfb(std::string(SPLAT_VIEWER_EXE) + " " + (dir / "run" / "model.ply").string() +
                                                  " --width 200 --height 200 --screenshot " + shot.string(),
                                              131),
                                   dir);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("cameras: " + (dir / "run" / "cameras_train.json").string()), std::string::npos) << r.out;
  EXPECT_GE(psnr(crop(read_image(shot), 0, 200), reference_render(conformance("lego_subset50k.ply"), dir)), 40.0);
}

TEST(ViewerCli, TwoModelsSideBySideWithANerfRefinedToFullResolution) {
  const fs::path dir = test::scratch_dir("viewer_cli_two");
  const fs::path nerf = dir / "tiny.nerf";
  test::write_tiny_nerf(nerf);
  const fs::path shot = dir / "two.png";
  const auto r = test::run_command(
      under_xvfb(std::string(SPLAT_VIEWER_EXE) + " " + conformance("lego_subset50k.ply") + " " + nerf.string() +
                 " --cameras " + conformance("transforms_test.json") + " --width 200 --height 200 --screenshot " +
                 shot.string(), 141),
      dir);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const Image viewer = read_image(shot);
  ASSERT_EQ(viewer.width, 400);
  EXPECT_GE(psnr(crop(viewer, 0, 200), reference_render(conformance("lego_subset50k.ply"), dir)), 40.0);
  EXPECT_GE(psnr(crop(viewer, 200, 200), reference_render(nerf.string(), dir)), 40.0);
}

TEST(ViewerCli, OrbitBenchmarkReportsEachPhase) {
  const fs::path dir = test::scratch_dir("viewer_cli_bench");
  const auto r = test::run_command(under_xvfb(std::string(SPLAT_VIEWER_EXE) + " " + conformance("lego_subset50k.ply") +
                                              " --width 160 --height 120 --bench-orbit 1", 161),
                                   dir);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const auto j = nlohmann::json::parse(r.out.substr(r.out.rfind("{\"width\"")));
  EXPECT_EQ(j.at("width").get<int>(), 160);
  for (const char* phase : {"full", "half", "adaptive"}) {
    SCOPED_TRACE(phase);
    EXPECT_GT(j.at(phase).at("frames").get<int>(), 0);
    EXPECT_GT(j.at(phase).at("fps").get<double>(), 0.0);
  }
  EXPECT_EQ(j.at("full").at("scale_median").get<double>(), 1.0);
  EXPECT_EQ(j.at("half").at("scale_median").get<double>(), 0.5);
}

TEST(ViewerCli, BadInputExitsTwoNamingTheFileWithoutAWindow) {
  const fs::path dir = test::scratch_dir("viewer_cli_bad");
  test::write_text(dir / "broken.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 5\nend_header\n");
  test::write_text(dir / "notes.txt", "not a model");
  // No display at all: these must fail on the input before any window is asked for.
  for (const std::string& file : {(dir / "missing.ply").string(), (dir / "broken.ply").string(),
                                  (dir / "notes.txt").string()}) {
    const auto r = test::run_command("env -u DISPLAY " + std::string(SPLAT_VIEWER_EXE) + " " + file, dir);
    EXPECT_EQ(r.exit_code, 2) << file;
    EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(fs::path(file).filename().string()), std::string::npos) << r.err;
  }
  const auto view = test::run_command(std::string(SPLAT_VIEWER_EXE) + " " + conformance("lego_subset50k.ply") +
                                          " --cameras " + conformance("transforms_test.json") + " --view 99",
                                      dir);
  EXPECT_EQ(view.exit_code, 2);
  EXPECT_NE(view.err.find("--view 99"), std::string::npos) << view.err;
  const auto none = test::run_command(std::string(SPLAT_VIEWER_EXE), dir);
  EXPECT_EQ(none.exit_code, 2);
}

}  // namespace
}  // namespace splat

namespace splat {
namespace {

// splat-train --snapshot-every writes the model so far while it runs (and the cameras with
// the first), removing it once model.ply is written; splat-viewer --watch shows what is there.
TEST(ViewerCli, WatchShowsTheSnapshotsOfARunningTraining) {
  const fs::path dir = test::scratch_dir("viewer_cli_watch");
  test::write_demo_dataset(dir / "data", 8, 2, 64, 2000);
  const fs::path out = dir / "out";
  // In the background, long enough to be seen running; --max-seconds ends it.
  const std::string train = std::string(SPLAT_TRAIN_EXE) + " --data " + (dir / "data").string() + " --out " +
                            out.string() + " --iters 100000 --max-seconds 8 --snapshot-every 0.5 --quiet --threads 1";
  ASSERT_EQ(std::system((train + " > " + (dir / "train.log").string() + " 2>&1 &").c_str()), 0);
  bool seen = false;
  for (int i = 0; i < 200 && !seen; ++i) {  // up to 20 s
    seen = fs::exists(out / "snapshot.ply") && fs::exists(out / "cameras_train.json");
    if (!seen) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_TRUE(seen) << test::read_file(dir / "train.log");
  const fs::path shot = dir / "watch.png";
  const auto r = test::run_command(under_xvfb(std::string(SPLAT_VIEWER_EXE) + " --watch " + out.string() +
                                                  " --width 96 --height 64 --screenshot " + shot.string(), 181),
                                   dir);
  EXPECT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_EQ(read_image(shot).width, 96);
  for (int i = 0; i < 600 && !fs::exists(out / "metrics.json"); ++i)  // up to 60 s
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_TRUE(fs::exists(out / "metrics.json")) << test::read_file(dir / "train.log");
  EXPECT_TRUE(fs::exists(out / "model.ply"));
  EXPECT_FALSE(fs::exists(out / "snapshot.ply"));  // the final model replaces it

  // Without a display: the folder is checked first, and models cannot be given with it.
  for (const auto& [args, expected] :
       std::vector<std::pair<std::string, std::string>>{
           {"--watch " + (dir / "nowhere").string(), "nowhere: no such folder"},
           {"--watch " + (dir / "train.log").string(), "train.log: is not a folder"},
           {"--watch " + out.string() + " " + (out / "model.ply").string(), "give no model files with it"}}) {
    const auto bad = test::run_command("env -u DISPLAY " + std::string(SPLAT_VIEWER_EXE) + " " + args, dir);
    EXPECT_EQ(bad.exit_code, 2) << args;
    EXPECT_NE(bad.err.find(expected), std::string::npos) << bad.err;
  }
  const auto zero = test::run_command(std::string(SPLAT_TRAIN_EXE) + " --data " + (dir / "data").string() +
                                          " --out " + (dir / "o2").string() + " --snapshot-every 0",
                                      dir);
  EXPECT_EQ(zero.exit_code, 2);
  EXPECT_NE(zero.err.find("option --snapshot-every must be a number from 0.1 to"), std::string::npos) << zero.err;
}

// Without a display the viewer says so in one line, with GLFW's reason in it (GLFW's own
// message printed beside ours made two).
TEST(ViewerCli, WithoutADisplayOneErrorLineGivesGlfwsReason) {
  const fs::path dir = test::scratch_dir("viewer_cli_no_display");
  ASSERT_EQ(test::run_command(std::string(SPLAT_DEMO_EXE) + " --out " + (dir / "demo").string() +
                                  " --gaussians 200 --views 1 --size 32", dir)
                .exit_code, 0);
  const auto r = test::run_command("env -u DISPLAY -u WAYLAND_DISPLAY " + std::string(SPLAT_VIEWER_EXE) + " " +
                                       (dir / "demo" / "model.ply").string(), dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err.rfind("error: cannot open a window: GLFW: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("(set DISPLAY, or run under xvfb-run)"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

}  // namespace
}  // namespace splat
