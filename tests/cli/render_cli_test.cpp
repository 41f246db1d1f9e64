// splat-render end to end: the command-line contract, the conformance renders through the
// CLI, the bench JSON, fly-throughs (--path: videos, PNG frames, NeRFs), and bad input (clear
// error, exit 2, nothing half-written).
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <sys/wait.h>

#include "splat/data/image_io.hpp"
#include "tests/cli_support.hpp"
#include "splat/data/transforms_json.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

struct CommandResult {
  int exit_code;
  std::string out, err;
};

std::string slurp(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// `environment` ("NAME=value ...") goes before the command, for the shell to set.
CommandResult run_render(const std::string& args, const std::filesystem::path& dir,
                         const std::string& environment = "") {
  const auto out_file = dir / "stdout.txt", err_file = dir / "stderr.txt";
  const std::string cmd = environment + " " + std::string(SPLAT_RENDER_EXE) + " " + args + " > " +
                          out_file.string() + " 2> " + err_file.string();
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out_file), slurp(err_file)};
}

std::string conformance(const std::string& name) {
  return (test::conformance_dir() / name).string();
}

TEST(RenderCli, RendersConformanceViewsAbove45Db) {
  const auto dir = test::scratch_dir("render_cli_conformance");
  const CommandResult r = run_render("--model " + conformance("lego_subset50k.ply") + " --cameras " +
                                         conformance("transforms_test.json") + " --width 400 --height 400" +
                                         " --bg 1,1,1 --png16 --out " + (dir / "out").string(),
                                     dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"r_0", "r_48", "r_96"}) {
    const Image ours = read_image(dir / "out" / (std::string(name) + ".png"));
    const Image reference = read_image(test::conformance_dir() / "reference" / (std::string(name) + ".png"));
    EXPECT_GE(psnr(ours, reference), 45.0) << name;
  }
  int pngs = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir / "out")) pngs += e.path().extension() == ".png";
  EXPECT_EQ(pngs, 13);
}

TEST(RenderCli, BenchPrintsTimingJsonLast) {
  const auto dir = test::scratch_dir("render_cli_bench");
  const CommandResult r = run_render("--model " + conformance("lego_subset50k.ply") + " --cameras " +
                                         conformance("transforms_test.json") +
                                         " --width 96 --height 64 --bench 2 --out " + (dir / "out").string(),
                                     dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string text = r.out;
  while (!text.empty() && text.back() == '\n') text.pop_back();
  const std::string last = text.substr(text.rfind('\n') + 1);
  const auto j = nlohmann::json::parse(last);
  EXPECT_EQ(j.at("frames").get<int>(), 13);
  EXPECT_EQ(j.at("width").get<int>(), 96);
  EXPECT_EQ(j.at("height").get<int>(), 64);
  EXPECT_GT(j.at("ms_per_frame").get<double>(), 0.0);
  EXPECT_NEAR(j.at("fps").get<double>(), 1000.0 / j.at("ms_per_frame").get<double>(), 1e-2);
}

void expect_clean_failure(const std::string& args, const std::string& expected_in_message,
                          const std::string& test_name) {
  const auto dir = test::scratch_dir(test_name);
  const CommandResult r = run_render(args + " --out " + (dir / "out").string(), dir);
  EXPECT_EQ(r.exit_code, 2) << args;
  EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find(expected_in_message), std::string::npos) << r.err;
  // Nothing is made before the inputs are known good: not even the output folder.
  EXPECT_FALSE(std::filesystem::exists(dir / "out")) << args;
}

TEST(RenderCli, BadInputsFailCleanly) {
  const auto dir = test::scratch_dir("render_cli_inputs");
  const auto bad_ply = dir / "bad.ply", bad_json = dir / "bad.json";
  test::write_text(bad_ply, "not a ply file\n");
  test::write_text(bad_json, "{\"frames\": [");
  const std::string cams = " --cameras " + conformance("transforms_test.json");
  const std::string model = " --model " + conformance("lego_subset50k.ply");
  expect_clean_failure("--model /nonexistent/model.ply" + cams, "/nonexistent/model.ply", "cli_missing_model");
  expect_clean_failure("--model " + bad_ply.string() + cams, bad_ply.string(), "cli_bad_ply");
  expect_clean_failure(model + " --cameras " + bad_json.string(), bad_json.string(), "cli_bad_json");
  expect_clean_failure(model + " --cameras /nonexistent/t.json", "/nonexistent/t.json", "cli_missing_json");
  expect_clean_failure(model + cams + " --bg 1,1", "--bg", "cli_bad_bg");
  expect_clean_failure(model + cams + " --width 100", "--height", "cli_width_only");
  expect_clean_failure(model + cams + " --frobnicate 3", "--frobnicate", "cli_unknown_option");
  expect_clean_failure(model + cams + " --bench x", "--bench", "cli_bad_bench");
  expect_clean_failure(" --model " + (dir / "model.nerf").string() + cams, "model.nerf", "cli_unknown_format");
  expect_clean_failure(cams, "--model", "cli_no_model");
  const auto bad_nerf = dir / "bad.nerf";
  test::write_text(bad_nerf, "SPLATNRF but not a model\n");
  expect_clean_failure(" --model " + bad_nerf.string() + cams, bad_nerf.string(), "cli_bad_nerf");
}

}  // namespace
}  // namespace splat

// ---- Fly-throughs (--path) ----

namespace splat {
namespace {

namespace fs = std::filesystem;

using test::have_tool;
using test::video_frame_count;

// Names in `dir` that the test did not put there (the captured output, a fake tool folder).
std::vector<std::string> made_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name != "stdout.txt" && name != "stderr.txt" && name != "bin") names.push_back(name);
  }
  return names;
}

std::string lego() { return " --model " + conformance("lego_subset50k.ply"); }

// The share of `image`'s pixels that are not the white background, and their centroid in
// units of the image's size.
struct Coverage {
  double share = 0;
  double x = 0, y = 0;
};
Coverage coverage(const Image& image) {
  Coverage c;
  std::size_t count = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      bool content = false;
      for (int k = 0; k < 3; ++k) content |= image.at(x, y, k) < 0.9f;
      if (!content) continue;
      ++count;
      c.x += (x + 0.5) / image.width;
      c.y += (y + 0.5) / image.height;
    }
  if (count == 0) return c;
  c.share = double(count) / double(image.pixel_count());
  c.x /= double(count);
  c.y /= double(count);
  return c;
}

// The model fills a good part of `image` (neither a speck nor cropped to a close-up), near its
// middle.
void expect_framed(const Image& image, const std::string& label) {
  const Coverage c = coverage(image);
  EXPECT_GT(c.share, 0.10) << label;
  EXPECT_LT(c.share, 0.80) << label;
  EXPECT_NEAR(c.x, 0.5, 0.15) << label;
  EXPECT_NEAR(c.y, 0.5, 0.15) << label;
}

TEST(RenderCli, OrbitVideoHoldsEveryFrame) {
  SPLAT_SKIP_WITHOUT_FFMPEG();
  const auto dir = test::scratch_dir("render_cli_orbit_video");
  const fs::path video = dir / "videos" / "o.mp4";  // the folder is created
  const CommandResult r =
      run_render(lego() + " --path orbit --frames 12 --width 64 --height 64 --video " + video.string(), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(video_frame_count(video), 12);
  EXPECT_NE(r.out.find("frame 12/12"), std::string::npos) << r.out;
  // Only the video: no temporary left beside it, and no PNGs without --out.
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir / "videos")) names.push_back(e.path().filename().string());
  EXPECT_EQ(names, std::vector<std::string>{"o.mp4"});
}

TEST(RenderCli, OrbitAndSpiralFramesShowTheModelCentredAndMoving) {
  for (const char* path : {"orbit", "spiral"}) {
    const auto dir = test::scratch_dir(std::string("render_cli_frames_") + path);
    const CommandResult r = run_render(lego() + " --path " + path + " --frames 4 --width 96 --height 64 --out " +
                                           (dir / "frames").string(),
                                       dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::vector<Image> frames;
    for (int i = 0; i < 4; ++i) {
      frames.push_back(read_image(dir / "frames" / ("frame_000" + std::to_string(i) + ".png")));
      ASSERT_EQ(frames.back().width, 96);
      ASSERT_EQ(frames.back().height, 64);
      expect_framed(frames.back(), std::string(path) + " frame " + std::to_string(i));  // from the Gaussians
    }
    EXPECT_LT(psnr(frames[0], frames[2]), 25.0) << path << ": the camera moves";
    EXPECT_EQ(std::distance(fs::directory_iterator(dir / "frames"), fs::directory_iterator()), 4);
  }
}

TEST(RenderCli, InterpolatePassesThroughTheCameraViews) {
  const auto dir = test::scratch_dir("render_cli_interpolate");
  const std::string cams = " --cameras " + conformance("transforms_test.json");
  // 13 views, 25 frames: view k is frame 2k, rendered exactly as splat-render renders the view.
  const CommandResult path = run_render(lego() + cams + " --path interpolate --frames 25 --width 80 --height 80 --out " +
                                            (dir / "frames").string(),
                                        dir);
  ASSERT_EQ(path.exit_code, 0) << path.err;
  const CommandResult views = run_render(lego() + cams + " --width 80 --height 80 --out " + (dir / "views").string(), dir);
  ASSERT_EQ(views.exit_code, 0) << views.err;
  const std::vector<CameraFrame> frames = load_transforms(conformance("transforms_test.json"));
  for (int k : {0, 1, 6, 12}) {
    char name[32];
    std::snprintf(name, sizeof(name), "frame_%04d.png", 2 * k);
    const std::string ours = slurp(dir / "frames" / name);
    EXPECT_FALSE(ours.empty()) << name;
    EXPECT_TRUE(ours == slurp(dir / "views" / (frames[std::size_t(k)].name + ".png"))) << name;
  }
  // Between views the picture is neither neighbour.
  const Image between = read_image(dir / "frames" / "frame_0001.png");
  EXPECT_LT(psnr(between, read_image(dir / "views" / (frames[0].name + ".png"))), 40.0);
  EXPECT_LT(psnr(between, read_image(dir / "views" / (frames[1].name + ".png"))), 40.0);
}

TEST(RenderCli, OrbitFollowsTheCapturesCameras) {
  // The conformance views look at the lego from about 4 units away: an orbit at their centre,
  // distance, height, up and field of view frames it.
  const auto dir = test::scratch_dir("render_cli_orbit_cameras");
  const std::string cams = " --cameras " + conformance("transforms_test.json");
  const CommandResult r = run_render(lego() + cams + " --path orbit --frames 8 --width 80 --height 80 --out " +
                                         (dir / "frames").string(),
                                     dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find(", 1), 4.03 away, 38 deg above, 40 deg field of view"), std::string::npos) << r.out;
  for (const char* frame : {"frame_0000.png", "frame_0003.png"}) expect_framed(read_image(dir / "frames" / frame), frame);
}

TEST(RenderCli, FlyThroughsFollowTheTrainingCamerasBesideTheModel) {
  // A model in a splat-train output folder: with no --cameras, its cameras_train.json frames
  // the orbit (the same frames as naming it) and gives interpolate its views.
  const auto dir = test::scratch_dir("render_cli_cameras_beside");
  fs::create_directories(dir / "run");
  fs::copy_file(conformance("lego_subset50k.ply"), dir / "run" / "model.ply");
  fs::copy_file(conformance("transforms_test.json"), dir / "run" / "cameras_train.json");
  const std::string model = " --model " + (dir / "run" / "model.ply").string();
  const std::string size = " --frames 3 --width 48 --height 48";
  const CommandResult implicit = run_render(model + " --path orbit" + size + " --out " + (dir / "implicit").string(), dir);
  ASSERT_EQ(implicit.exit_code, 0) << implicit.err;
  EXPECT_NE(implicit.out.find("cameras: " + (dir / "run" / "cameras_train.json").string()), std::string::npos)
      << implicit.out;
  EXPECT_NE(implicit.out.find(", 1), 4.03 away, 38 deg above, 40 deg field of view"), std::string::npos) << implicit.out;
  const CommandResult named = run_render(model + " --cameras " + conformance("transforms_test.json") + " --path orbit" +
                                             size + " --out " + (dir / "named").string(),
                                         dir);
  ASSERT_EQ(named.exit_code, 0) << named.err;
  for (const char* frame : {"frame_0000.png", "frame_0002.png"})
    EXPECT_TRUE(slurp(dir / "implicit" / frame) == slurp(dir / "named" / frame)) << frame;
  const CommandResult through = run_render(model + " --path interpolate" + size + " --out " + (dir / "through").string(), dir);
  EXPECT_EQ(through.exit_code, 0) << through.err;
  EXPECT_TRUE(fs::exists(dir / "through" / "frame_0002.png"));
}

TEST(RenderCli, FlyThroughANerf) {
  const auto dir = test::scratch_dir("render_cli_nerf_path");
  const fs::path nerf = dir / "tiny.nerf";
  test::write_tiny_nerf(nerf);
  const bool video = have_tool("ffmpeg") && have_tool("ffprobe");
  const std::string video_args = video ? " --video " + (dir / "n.webm").string() : "";
  const CommandResult r = run_render("--model " + nerf.string() + " --path spiral --frames 3 --width 16 --height 16" +
                                         video_args + " --out " + (dir / "frames").string(),
                                     dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (int i = 0; i < 3; ++i) {
    const Image frame = read_image(dir / "frames" / ("frame_000" + std::to_string(i) + ".png"));
    EXPECT_EQ(frame.width, 16);
  }
  if (video) {
    EXPECT_EQ(video_frame_count(dir / "n.webm"), 3);
  }
}

// Exit 2, one "error:" line holding `expected`, and nothing made in the scratch folder.
void expect_clean_path_failure(const std::string& args, const std::string& expected, const fs::path& dir,
                               const std::string& environment = "") {
  const CommandResult r = run_render(args, dir, environment);
  EXPECT_EQ(r.exit_code, 2) << args;
  EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find(expected), std::string::npos) << args << " -> " << r.err;
  for (const std::string& name : made_in(dir)) ADD_FAILURE() << args << " left " << name;
}

TEST(RenderCli, FlyThroughBadArgumentsFailCleanly) {
  const auto dir = test::scratch_dir("render_cli_path_args");
  const std::string d = dir.string();
  const std::string out = " --out " + d + "/frames", video = " --video " + d + "/v/o.mp4";
  const std::string cams = " --cameras " + conformance("transforms_test.json");
  expect_clean_path_failure(lego() + " --path zigzag" + out, "orbit, spiral or interpolate", dir);
  expect_clean_path_failure(lego() + " --path orbit --frames 0" + out, "--frames", dir);
  expect_clean_path_failure(lego() + " --path orbit --frames 1000000" + out, "--frames", dir);
  expect_clean_path_failure(lego() + " --path orbit --frames x" + out, "--frames", dir);
  expect_clean_path_failure(lego() + " --path interpolate" + out, "--cameras", dir);
  expect_clean_path_failure(lego() + " --path orbit", "--video", dir);
  expect_clean_path_failure(lego() + " --path orbit --video " + d + "/v/o.avi", "o.avi: cannot write a '.avi' video", dir);
  expect_clean_path_failure(lego() + " --path orbit --width 63 --height 64" + video, "even", dir);
  expect_clean_path_failure(lego() + " --path orbit --fps 0" + video, "--fps", dir);
  expect_clean_path_failure(lego() + " --path orbit --bench 2" + out, "--bench", dir);
  expect_clean_path_failure(lego() + cams + " --frames 5" + out, "--frames goes with --path", dir);
  // Bad inputs are found before anything is made.
  expect_clean_path_failure(" --model " + d + "/none.ply --path orbit" + out + video, d + "/none.ply", dir);
  expect_clean_path_failure(lego() + " --cameras " + d + "/none.json --path orbit" + out + video, d + "/none.json", dir);
}

TEST(RenderCli, FlyThroughWithoutOrWithAFailingFfmpegLeavesNothing) {
  const auto dir = test::scratch_dir("render_cli_path_ffmpeg");
  const std::string d = dir.string();
  const std::string args = lego() + " --path orbit --frames 3 --width 32 --height 32 --video " + d + "/v/o.mp4";
  // No ffmpeg on the PATH: one line saying how to install it, before the model is read.
  fs::create_directories(dir / "bin");
  expect_clean_path_failure(args + " --out " + d + "/frames", "apt-get install ffmpeg", dir,
                            "PATH=" + (dir / "bin").string());
  // An ffmpeg that fails at once (the frames meet a closed pipe) or after reading them all:
  // its message comes through, and neither the video nor its temporary remains.
  for (const char* body : {"", "cat > /dev/null; "}) {
    test::write_text(dir / "bin" / "ffmpeg",
                     std::string("#!/bin/sh\n") + body + "echo 'x264: out of cheese' >&2\nexit 3\n");
    fs::permissions(dir / "bin" / "ffmpeg", fs::perms::owner_all);
    const CommandResult r = run_render(args, dir, "PATH=" + (dir / "bin").string() + ":/usr/bin:/bin");
    EXPECT_EQ(r.exit_code, 2) << body;
    EXPECT_NE(r.err.find(d + "/v/o.mp4: ffmpeg failed (exit status 3): x264: out of cheese"), std::string::npos)
        << body << " -> " << r.err;
    EXPECT_TRUE(fs::is_empty(dir / "v")) << body;
  }
}

}  // namespace
}  // namespace splat
