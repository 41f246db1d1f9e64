// splat-convert end to end: the formats by extension, what it prints, the renderer opening
// its outputs, and bad input (one error line, exit 2, no output file).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "splat/data/image_io.hpp"
#include "splat/eval/metrics.hpp"
#include "tests/cli_support.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

std::string convert(const std::string& args) { return std::string(SPLAT_CONVERT_EXE) + " " + args; }

std::string conformance_model() { return (test::conformance_dir() / "lego_subset50k.ply").string(); }

// Renders view r_0 of the conformance cameras at 200² into `out`.
test::CommandResult render(const fs::path& model, const fs::path& out, const fs::path& dir) {
  return test::run_command(std::string(SPLAT_RENDER_EXE) + " --model " + model.string() + " --cameras " +
                               (test::conformance_dir() / "transforms_test.json").string() +
                               " --width 200 --height 200 --out " + out.string(),
                           dir);
}

TEST(ConvertCli, PlyToSpzAndBackRendersWithin40DbAndTheRendererOpensEveryFormat) {
  const fs::path dir = test::scratch_dir("convert_cli_round_trip");
  test::CommandResult r = test::run_command(convert(conformance_model() + " " + (dir / "m.spz").string()), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("50000 Gaussians, SH degree 3"), std::string::npos) << r.out;
  EXPECT_LT(fs::file_size(dir / "m.spz") * 5, fs::file_size(conformance_model()));
  r = test::run_command(convert((dir / "m.spz").string() + " " + (dir / "back.ply").string()), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = test::run_command(convert(conformance_model() + " " + (dir / "m.splat").string()), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("SH bands 1-3 (view-dependent colour) were dropped"), std::string::npos) << r.out;
  EXPECT_EQ(fs::file_size(dir / "m.splat"), 50000u * 32);

  ASSERT_EQ(render(conformance_model(), dir / "ply", dir).exit_code, 0);
  for (const char* model : {"back.ply", "m.spz", "m.splat"}) {
    const test::CommandResult rendered = render(dir / model, dir / (std::string("out_") + model), dir);
    ASSERT_EQ(rendered.exit_code, 0) << rendered.err;
    const double db = psnr(read_image(dir / "ply" / "r_0.png"), read_image(dir / (std::string("out_") + model) / "r_0.png"));
    EXPECT_GE(db, std::string(model) == "m.splat" ? 30.0 : 40.0) << model;
  }
}

TEST(ConvertCli, BadInputIsOneErrorLineAndNoOutput) {
  const fs::path dir = test::scratch_dir("convert_cli_bad_input");
  const std::string out = (dir / "out.spz").string();
  const struct {
    std::string args, message;
  } cases[] = {
      {conformance_model(), "expected IN and OUT"},
      {(dir / "absent.ply").string() + " " + out, "absent.ply: file does not exist"},
      {conformance_model() + " " + (dir / "out.obj").string(), "out.obj: the output's extension must name"},
      {conformance_model() + " " + out + " --spz-sh-bits 9,9", "option --spz-sh-bits must be 2 comma-separated values, each a whole number from 1 to 8"},
      {conformance_model() + " " + out + " --spz-sh-bits 6", "option --spz-sh-bits must be 2 comma-separated values"},
      {conformance_model() + " " + conformance_model(), "the output is the input file"},
  };
  for (const auto& c : cases) {
    const test::CommandResult r = test::run_command(convert(c.args), dir);
    EXPECT_EQ(r.exit_code, 2) << c.args;
    EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line: " << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out)) << c.args;
    EXPECT_FALSE(fs::exists(dir / "out.obj"));
  }
}

}  // namespace
}  // namespace splat
