// splat-grad end to end: the contract's output against the official gradients, and bad input
// (clear error, exit 2, nothing written).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>

#include "tests/cli_support.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

std::string conformance(const std::string& name) {
  return (test::conformance_dir() / name).string();
}

std::string grad_command(const std::string& overrides_view, const std::string& weights,
                         const fs::path& out) {
  return std::string(SPLAT_GRAD_EXE) + " --model " + conformance("lego_subset50k.ply") +
         " --cameras " + conformance("transforms_test.json") + " " + overrides_view +
         " --width 400 --height 400 --bg 1,1,1 --weights " + weights + " --out " + out.string();
}

TEST(GradCli, MatchesOfficialGradientsThroughTheContract) {
  const fs::path dir = test::scratch_dir("grad_cli_conformance");
  const auto r = test::run_command(grad_command("--view 0", conformance("gradients/W_r_0.f32"), dir / "g.f32") +
                                       " --compare " + conformance("gradients/grad_r_0.f32") + " --bench 2",
                                   dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(fs::file_size(dir / "g.f32"), 50000u * 59 * 4);
  const auto loss = nlohmann::json::parse(test::last_line(r.out)).at("loss").get<double>();
  EXPECT_NEAR(loss, -256.915888, 1e-4 * 256.915888);
  // Every group's relative error is printed; all must be within the bar.
  int groups = 0;
  std::size_t pos = 0;
  while ((pos = r.out.find("relative error ", pos)) != std::string::npos) {
    pos += 15;
    EXPECT_LE(std::stod(r.out.substr(pos)), 1e-3) << r.out;
    ++groups;
  }
  EXPECT_EQ(groups, 6);
  EXPECT_NE(r.out.find("bench 2 pairs: forward median "), std::string::npos) << r.out;
}

TEST(GradCli, BadInputsFailCleanly) {
  const fs::path dir = test::scratch_dir("grad_cli_bad");
  test::write_text(dir / "short.f32", std::string(1000, '\0'));
  // The right size, but one weight is NaN: the loss and every gradient would be NaN.
  std::string nan_weights = test::read_file(conformance("gradients/W_r_0.f32"));
  const float nan = std::nanf("");
  std::memcpy(nan_weights.data() + 4 * 1234, &nan, sizeof(nan));
  test::write_text(dir / "nan.f32", nan_weights);
  const std::string good_weights = conformance("gradients/W_r_0.f32");
  struct Case {
    std::string command, expected;
  };
  const Case cases[] = {
      {grad_command("--view 0", (dir / "short.f32").string(), dir / "g.f32"), "short.f32"},
      {grad_command("--view 0", (dir / "nan.f32").string(), dir / "g.f32"), "nan.f32: the weight image: value 1234 is not finite"},
      {grad_command("--view 13", good_weights, dir / "g.f32"), "out of range"},
      {grad_command("--view -1", good_weights, dir / "g.f32"), "option --view must be a whole number from 0"},
      {grad_command("--view 0", (dir / "missing.f32").string(), dir / "g.f32"), "missing.f32"},
      {std::string(SPLAT_GRAD_EXE) + " --model /nonexistent.ply --cameras " + conformance("transforms_test.json") +
           " --view 0 --width 400 --height 400 --bg 1,1,1 --weights " + good_weights + " --out " +
           (dir / "g.f32").string(),
       "/nonexistent.ply"},
      {grad_command("", good_weights, dir / "g.f32"), "--view"},
      {grad_command("--view 0 --bench 0", good_weights, dir / "g.f32"), "--bench"},
  };
  for (const Case& c : cases) {
    const auto r = test::run_command(c.command, dir);
    EXPECT_EQ(r.exit_code, 2) << c.command;
    EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(c.expected), std::string::npos) << c.command << " -> " << r.err;
    EXPECT_FALSE(fs::exists(dir / "g.f32")) << "a failed run left an output file";
  }
}

}  // namespace
}  // namespace splat
