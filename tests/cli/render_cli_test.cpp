// splat-render end to end: the command-line contract, the conformance renders through the
// CLI, the bench JSON, and bad input (clear error, exit 2, nothing half-written).
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <sys/wait.h>

#include "splat/data/image_io.hpp"
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

CommandResult run_render(const std::string& args, const std::filesystem::path& dir) {
  const auto out_file = dir / "stdout.txt", err_file = dir / "stderr.txt";
  const std::string cmd = std::string(SPLAT_RENDER_EXE) + " " + args + " > " +
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
  // Nothing half-written: no temporary files and no PNGs.
  if (std::filesystem::exists(dir / "out"))
    for (const auto& e : std::filesystem::directory_iterator(dir / "out"))
      ADD_FAILURE() << "left behind: " << e.path();
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
}

}  // namespace
}  // namespace splat
