// What every program shares (apps/common/arg_parser.hpp): -h, --version, --name=value, the
// nearest option suggested for a misspelt one, and one --bg syntax.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "splat/data/image_io.hpp"
#include "tests/cli_support.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

// Each program with an option of its own to misspell.
const std::vector<std::pair<std::string, std::string>>& programs() {
  static const std::vector<std::pair<std::string, std::string>> list = {
      {SPLAT_RENDER_EXE, "camera"},   {SPLAT_TRAIN_EXE, "iter"},       {SPLAT_EVAL_EXE, "method"},
      {SPLAT_PSNR_EXE, "gb"},         {SPLAT_CONVERT_EXE, "spz-sh-bit"}, {SPLAT_PROCESS_EXE, "image"},
      {SPLAT_SCENE_EXE, "outt"},      {SPLAT_GRAD_EXE, "weight"},      {SPLAT_VIEWER_EXE, "screenshott"}};
  return list;
}

TEST(Conventions, EveryProgramTakesDashHVersionAndSuggestsTheNearestOption) {
  const auto dir = test::scratch_dir("conventions_cli");
  for (const auto& [exe, misspelt] : programs()) {
    const std::string name = std::filesystem::path(exe).filename().string();
    test::CommandResult r = test::run_command(exe + " -h", dir);
    EXPECT_EQ(r.exit_code, 0) << name << r.err;
    EXPECT_NE(r.out.find("usage"), std::string::npos) << name << ": " << r.out;
    r = test::run_command(exe + " --version", dir);
    EXPECT_EQ(r.exit_code, 0) << name;
    EXPECT_EQ(r.out, name + " 0.1.0\n");
    r = test::run_command(exe + " --" + misspelt + " 1", dir);
    EXPECT_EQ(r.exit_code, 2) << name;
    EXPECT_NE(r.err.find("unknown option --" + misspelt + " (did you mean --"), std::string::npos) << name << ": " << r.err;
  }
  const test::CommandResult r = test::run_command(std::string(SPLAT_TRAIN_EXE) + " --zzzzzzzz 1", dir);
  EXPECT_NE(r.err.find("unknown option --zzzzzzzz (see --help)"), std::string::npos) << r.err;
}

TEST(Conventions, NameEqualsValueIsNameValue) {
  const auto dir = test::scratch_dir("conventions_cli_equals");
  const std::string model = (test::conformance_dir() / "lego_subset50k.ply").string();
  test::CommandResult r = test::run_command(std::string(SPLAT_CONVERT_EXE) + " " + model + " " +
                                                (dir / "m.spz").string() + " --spz-sh-bits=9,9",
                                            dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("option --spz-sh-bits must be 2 comma-separated values, each a whole number from 1 to 8"), std::string::npos) << r.err;
  r = test::run_command(std::string(SPLAT_CONVERT_EXE) + " " + model + " " + (dir / "m.spz").string() +
                            " --spz-sh-bits=8,8",
                        dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = test::run_command(std::string(SPLAT_CONVERT_EXE) + " --help=yes", dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("option --help takes no value"), std::string::npos) << r.err;
}

// white, black and R,G,B mean the same everywhere: the same mid-grey render scored against a
// fully transparent truth image composited onto each of them.
TEST(Conventions, BgIsWhiteBlackOrRgbInEveryProgram) {
  const auto dir = test::scratch_dir("conventions_cli_bg");
  Image transparent(4, 4, 4), grey(4, 4, 3);
  std::fill(grey.data.begin(), grey.data.end(), 0.5f);
  write_png(transparent, dir / "truth.png", 16);
  write_png(grey, dir / "grey.png", 16);
  const std::string psnr = std::string(SPLAT_PSNR_EXE) + " " + (dir / "grey.png").string() + " " +
                           (dir / "truth.png").string() + " --bg ";
  for (const char* same : {"0.5,0.5,0.5", "0.5,.5,5e-1"}) {
    const test::CommandResult r = test::run_command(psnr + same, dir);
    ASSERT_EQ(r.exit_code, 0) << same << r.err;
    EXPECT_GT(std::stod(r.out), 90.0) << same;
  }
  for (const char* extreme : {"white", "black", "1,1,1", "0,0,0"}) {
    const test::CommandResult r = test::run_command(psnr + extreme, dir);
    ASSERT_EQ(r.exit_code, 0) << extreme << r.err;
    EXPECT_NEAR(std::stod(r.out), 6.02, 0.01) << extreme;  // off by 0.5 everywhere
  }
  // Every program that takes --bg refuses the same malformed colours, before reading anything.
  // (The files named do not exist: the option is checked first.)
  const std::vector<std::pair<std::string, std::string>> takers = {
      {SPLAT_PSNR_EXE, "a.png b.png"},
      {SPLAT_RENDER_EXE, "--model m.ply --cameras c.json --out o"},
      {SPLAT_TRAIN_EXE, "--data d --out o"},
      {SPLAT_EVAL_EXE, "--data d --out o"},
      {SPLAT_VIEWER_EXE, "m.ply"},
      {SPLAT_GRAD_EXE, "--model m.ply --cameras c.json --view 0 --width 8 --height 8 --weights w --out g"}};
  for (const auto& [exe, args] : takers)
    for (const char* bad : {"green", "1,1", "1,1,1,1", "2,0,0", "-0.1,0,0", "nan,0,0", "1,,1"}) {
      const test::CommandResult r = test::run_command(exe + " " + args + " --bg " + bad, dir);
      EXPECT_EQ(r.exit_code, 2) << exe << " " << bad;
      EXPECT_NE(r.err.find("option --bg expects white, black or R,G,B with each in [0, 1], got '" +
                           std::string(bad) + "'"),
                std::string::npos)
          << exe << " " << bad << ": " << r.err;
    }
}

}  // namespace
}  // namespace splat
