// Faults, not bad files: splat-train killed (SIGKILL) at random moments never leaves a model
// or a checkpoint on disk that does not load, and --resume always continues; a write stopped
// by the file-size limit (ulimit -f, as a full disk would) is one clean error naming the file,
// and the outputs of the previous run stay as they were.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>

#include "tests/cli_support.hpp"
#include "splat/gaussians/ply_io.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

fs::path small_dataset(const fs::path& dir) {
  test::write_demo_dataset(dir / "data", 6, 2, 32, 1000);
  test::write_text(dir / "small.json", R"({"random_init_points": 2000})");
  return dir / "data";
}

std::string train(const fs::path& dir, const fs::path& out, const std::string& extra) {
  return std::string(SPLAT_TRAIN_EXE) + " --data " + (dir / "data").string() + " --out " + out.string() +
         " --config " + (dir / "small.json").string() + " --quiet --test-every 0 --threads 1 " + extra;
}

std::vector<std::string> temporaries(const fs::path& folder) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder))
    if (entry.path().filename().string().rfind(".tmp-", 0) == 0) names.push_back(entry.path().string());
  return names;
}

TEST(Faults, KilledAtRandomMomentsTheFilesOnDiskLoadAndResumeContinues) {
  const fs::path dir = test::scratch_dir("faults_kill");
  small_dataset(dir);
  const fs::path out = dir / "run";
  const auto checkpoint_iteration = [&] {
    return test::split_checkpoint(test::read_file(out / "checkpoint.ckpt")).header.at("iteration").get<int>();
  };
  // The tiny run makes ~2,000 iterations a second (a few hundred under the sanitizers) and
  // checkpoints every 10: each round asks for 100 to 4,000 more iterations than the checkpoint
  // holds and is killed after 20 to 1,500 ms, so most are killed mid-run, and many of those
  // mid-write. Every fifth round is left to finish (writing model.ply) whatever the speed.
  std::mt19937 rng(2026);
  std::uniform_int_distribution<int> more_iterations(100, 4000), delay_ms(20, 1500);
  int killed = 0, finished = 0;
  for (int round = 0; round < 20; ++round) {
    SCOPED_TRACE("round " + std::to_string(round));
    const bool resume = fs::exists(out / "checkpoint.ckpt");
    const bool runs_to_the_end = round % 5 == 4;
    const int more = more_iterations(rng), delay = delay_ms(rng);
    const int target = (resume ? checkpoint_iteration() : 0) + (runs_to_the_end ? 20 : more);
    const std::string kill = runs_to_the_end ? "" : "sleep " + std::to_string(delay / 1000.0) + "; kill -KILL $pid 2>/dev/null; ";
    const std::string command =
        "(" + train(dir, out, "--iters " + std::to_string(target) + " --checkpoint-every 10" +
                                  (resume ? " --resume " + out.string() : "")) +
        " & pid=$!; " + kill + "wait $pid; echo $? > " + (dir / "code").string() + ")";
    test::run_command(command, dir);
    const int code = std::stoi(test::read_file(dir / "code"));
    ASSERT_TRUE(code == 0 || code == 128 + 9) << "exit " << code << ": " << test::read_file(dir / "stderr.txt");
    (code == 0 ? finished : killed) += 1;
    if (fs::exists(out / "model.ply")) {
      EXPECT_NO_THROW(read_ply(out / "model.ply"));
    }
    if (fs::exists(out / "checkpoint.ckpt")) {
      EXPECT_NO_THROW(checkpoint_iteration());
    }
  }
  EXPECT_GE(killed, 5);
  EXPECT_GE(finished, 4);
  // The checkpoint left by the last round resumes, and the run completes.
  ASSERT_TRUE(fs::exists(out / "checkpoint.ckpt"));
  const auto r = test::run_command(
      train(dir, out, "--iters " + std::to_string(checkpoint_iteration() + 50) + " --resume " + out.string()), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_GT(read_ply(out / "model.ply").size(), 0u);
}

TEST(Faults, AWriteStoppedByTheFileSizeLimitIsACleanErrorAndKeepsThePreviousOutputs) {
  const fs::path dir = test::scratch_dir("faults_file_size");
  small_dataset(dir);
  const fs::path out = dir / "run";
  auto r = test::run_command(train(dir, out, "--iters 30"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string model = test::read_file(out / "model.ply");
  ASSERT_GT(model.size(), 100'000u) << "the model must be larger than the limit below";
  // Another seed: every output would change. 64 blocks (32 or 64 KiB) stop the model's write.
  r = test::run_command("ulimit -f 64; " + train(dir, out, "--iters 30 --seed 1"), dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err.rfind("error: " + out.string() + "/", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("File too large"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_TRUE(test::read_file(out / "model.ply") == model) << "the previous model.ply was changed";
  EXPECT_TRUE(temporaries(out).empty()) << temporaries(out).front();
}

}  // namespace
}  // namespace splat
