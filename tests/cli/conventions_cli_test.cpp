// What every program shares (apps/common/arg_parser.hpp): -h, --version, --name=value, and
// the nearest option suggested for a misspelt one.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

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
  EXPECT_NE(r.err.find("--spz-sh-bits values must be 1..8"), std::string::npos) << r.err;
  r = test::run_command(std::string(SPLAT_CONVERT_EXE) + " " + model + " " + (dir / "m.spz").string() +
                            " --spz-sh-bits=8,8",
                        dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = test::run_command(std::string(SPLAT_CONVERT_EXE) + " --help=yes", dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("option --help takes no value"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace splat
