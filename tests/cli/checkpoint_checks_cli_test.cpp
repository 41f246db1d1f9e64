// --resume with a damaged checkpoint: every value of its header is checked (ranges, the
// random generator's state) and every parameter must be finite, so a bad file is one clean
// error naming it, never a hang, an overflow or a model that cannot be saved.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>

#include <nlohmann/json.hpp>

#include "tests/cli_support.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

std::string train(const fs::path& data, const fs::path& out, const std::string& extra) {
  return std::string(SPLAT_TRAIN_EXE) + " --data " + data.string() + " --out " + out.string() +
         " --quiet --test-every 0 " + extra;
}

TEST(CheckpointChecks, DamagedSplatCheckpointsAreCleanErrorsNamingTheFile) {
  const fs::path dir = test::scratch_dir("checkpoint_checks_splat");
  test::write_demo_dataset(dir / "data", 6, 2, 32, 1000);
  test::write_text(dir / "small.json", R"({"random_init_points": 2000})");
  auto r = test::run_command(
      train(dir / "data", dir / "run", "--iters 20 --checkpoint-every 20 --config " + (dir / "small.json").string()),
      dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string original = test::read_file(dir / "run" / "checkpoint.ckpt");

  struct Damage {
    const char* what;
    std::function<void(test::CheckpointParts&)> apply;
    const char* expected;  // in the message besides the file name
  };
  const Damage damages[] = {
      {"iteration 1e12", [](test::CheckpointParts& p) { p.header["iteration"] = 1e12; }, "iteration"},
      {"negative iteration", [](test::CheckpointParts& p) { p.header["iteration"] = -7; }, "iteration"},
      {"SH degree 9", [](test::CheckpointParts& p) { p.header["sh_degree"] = 9; }, "sh_degree"},
      {"garbage RNG", [](test::CheckpointParts& p) { p.header["rng"] = "not a state at all"; }, "rng"},
      {"bad config value", [](test::CheckpointParts& p) { p.header["config"]["seed"] = -5; }, "seed"},
      {"NaN parameter",
       [](test::CheckpointParts& p) {
         const float nan = std::nanf("");
         std::memcpy(p.arrays.data() + 8, &nan, sizeof(nan));  // the first mean
       },
       "not finite"},
  };
  for (const Damage& damage : damages) {
    test::CheckpointParts parts = test::split_checkpoint(original);
    damage.apply(parts);
    const fs::path bad = dir / "bad.ckpt";
    test::write_text(bad, test::join_checkpoint(parts));
    r = test::run_command(train(dir / "data", dir / "resumed", "--iters 40 --resume " + bad.string()), dir);
    EXPECT_EQ(r.exit_code, 2) << damage.what;
    EXPECT_EQ(r.err.rfind("error: " + bad.string() + ": ", 0), 0u) << damage.what << ": " << r.err;
    EXPECT_NE(r.err.find(damage.expected), std::string::npos) << damage.what << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << damage.what << ": one line: " << r.err;
    EXPECT_FALSE(fs::exists(dir / "resumed" / "model.ply")) << damage.what << ": nothing written";
  }
  // Another dataset with as many views (other pixels): the checkpoint's fingerprint of its
  // training images refuses it.
  test::write_demo_dataset(dir / "other", 6, 2, 32, 1500);
  r = test::run_command(train(dir / "other", dir / "resumed", "--iters 40 --resume " + (dir / "run").string()), dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("checkpoint.ckpt: checkpoint was written for other training images"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "resumed"));
}

}  // namespace
}  // namespace splat
