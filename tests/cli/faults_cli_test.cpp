// Faults, not bad files: splat-train killed (SIGKILL) at random moments never leaves a model
// or a checkpoint on disk that does not load, and --resume always continues; a write stopped
// by the file-size limit (ulimit -f, as a full disk would) is one clean error naming the file,
// and the outputs of the previous run stay as they were.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "tests/cli_support.hpp"
#include "splat/gaussians/ply_io.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

fs::path small_dataset(const fs::path& dir) {
  test::write_demo_dataset(dir / "data", 6, 2, 32, 1000);
  // The compact schedule spans the first run's --iters unless the config fixes it: fixed here,
  // so that runs of any length (killed ones aim far) share it and resume to the same model.
  test::write_text(dir / "small.json", R"({"random_init_points": 2000, "schedule_iterations": 5000})");
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

// A write stopped by the file-size limit: exit 2, one line "error: <named>…File too large".
void expect_file_too_large(const test::CommandResult& r, const std::string& named) {
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err.rfind("error: " + named, 0), 0u) << r.err;
  EXPECT_NE(r.err.find("File too large"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(Faults, KilledAtRandomMomentsTheFilesOnDiskLoadAndResumeContinues) {
  const fs::path dir = test::scratch_dir("faults_kill");
  small_dataset(dir);
  const fs::path out = dir / "run";
  const auto checkpoint_iteration = [&] {
    return test::split_checkpoint(test::read_file(out / "checkpoint.ckpt")).header.at("iteration").get<int>();
  };
  // The tiny run makes ~2,000 iterations a second (a few hundred under the sanitizers) and
  // checkpoints every 10: each round resumes the last checkpoint towards an iteration count it
  // never reaches and is killed after 20 to 1,500 ms, many times mid-write. Every fifth round
  // instead resumes a copy of the folder to its end (writing model.ply): a run that ends
  // finishes its model (the last iteration prunes), so the killed chain must not end, for its
  // model to be the one an uninterrupted run makes.
  std::mt19937 rng(2026);
  std::uniform_int_distribution<int> delay_ms(20, 1500);
  int killed = 0, finished = 0;
  for (int round = 0; round < 20; ++round) {
    SCOPED_TRACE("round " + std::to_string(round));
    const bool resume = fs::exists(out / "checkpoint.ckpt");
    const bool runs_to_the_end = resume && round % 5 == 4;
    const int delay = delay_ms(rng);
    fs::path folder = out;
    if (runs_to_the_end) {
      folder = dir / "finished";
      fs::remove_all(folder);
      fs::copy(out, folder);
    }
    const int target = (resume ? checkpoint_iteration() : 0) + (runs_to_the_end ? 20 : 1'000'000);
    const std::string kill = runs_to_the_end ? "" : "sleep " + std::to_string(delay / 1000.0) + "; kill -KILL $pid 2>/dev/null; ";
    const std::string run = train(dir, folder, "--iters " + std::to_string(target) + " --checkpoint-every 10" +
                                                   (resume ? " --resume " + folder.string() : ""));
    const std::string command = "(" + run + " & pid=$!; " + kill + "wait $pid; echo $? > " + (dir / "code").string() + ")";
    test::run_command(command, dir);
    const int code = std::stoi(test::read_file(dir / "code"));
    ASSERT_TRUE(code == (runs_to_the_end ? 0 : 128 + 9)) << "exit " << code << ": " << test::read_file(dir / "stderr.txt");
    (code == 0 ? finished : killed) += 1;
    if (fs::exists(folder / "model.ply")) {
      EXPECT_NO_THROW(read_ply(folder / "model.ply"));
    }
    if (fs::exists(out / "checkpoint.ckpt")) {
      EXPECT_NO_THROW(checkpoint_iteration());
    }
  }
  EXPECT_GE(killed, 12);
  EXPECT_GE(finished, 3);
  // The checkpoint left by the last round resumes, and the run completes with the model a run
  // never interrupted makes.
  ASSERT_TRUE(fs::exists(out / "checkpoint.ckpt"));
  const std::string target = std::to_string(checkpoint_iteration() + 50);
  auto r = test::run_command(train(dir, out, "--iters " + target + " --resume " + out.string()), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = test::run_command(train(dir, dir / "straight", "--iters " + target), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(test::read_file(out / "model.ply") == test::read_file(dir / "straight" / "model.ply"))
      << "after " << killed << " kills the resumed model differs from the uninterrupted run's at " << target;
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
  expect_file_too_large(r, out.string() + "/");
  EXPECT_TRUE(test::read_file(out / "model.ply") == model) << "the previous model.ply was changed";
  EXPECT_TRUE(temporaries(out).empty()) << temporaries(out).front();
}

// A checkpoint write and a report stopped by the file-size limit (a full disk, for the writer)
// are clean errors naming the file, and the previous checkpoint and report stay as they were.
TEST(Faults, CheckpointAndReportWritesStoppedByTheFileSizeLimitKeepThePreviousFiles) {
  const fs::path dir = test::scratch_dir("faults_checkpoint_report");
  small_dataset(dir);
  const fs::path out = dir / "run";
  auto r = test::run_command(train(dir, out, "--iters 20 --checkpoint-every 10"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string checkpoint = test::read_file(out / "checkpoint.ckpt");
  ASSERT_GT(checkpoint.size(), 100'000u);
  // Resumed, the first checkpoint it writes (at 30) is stopped.
  r = test::run_command("ulimit -f 64; " + train(dir, out, "--iters 40 --checkpoint-every 10 --resume " + out.string()),
                        dir);
  expect_file_too_large(r, (out / "checkpoint.ckpt").string() + ": ");
  EXPECT_TRUE(test::read_file(out / "checkpoint.ckpt") == checkpoint) << "the previous checkpoint was changed";
  EXPECT_TRUE(temporaries(out).empty()) << temporaries(out).front();

  // splat-eval --report: the results of a short comparison, then a history long enough that
  // the report cannot be written under the limit.
  const fs::path eval = dir / "eval";
  r = test::run_command(std::string(SPLAT_EVAL_EXE) + " --data " + (dir / "data").string() + " --out " + eval.string() +
                            " --methods splat --max-seconds 1 --threads 1 --quiet --splat-config " +
                            (dir / "small.json").string(),
                        dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string report = test::read_file(eval / "report.html");
  nlohmann::json results = nlohmann::json::parse(test::read_file(eval / "results.json"));
  nlohmann::json& history = results["methods"][0]["history"];
  const nlohmann::json entry = history.back();
  for (int i = 0; i < 2000; ++i) history.push_back(entry);  // charts' data and page beyond 1 block
  test::write_text(eval / "results.json", results.dump());
  r = test::run_command("ulimit -f 1; " + std::string(SPLAT_EVAL_EXE) + " --report --quiet --out " + eval.string(),
                        dir);
  expect_file_too_large(r, eval.string() + "/");
  EXPECT_TRUE(test::read_file(eval / "report.html") == report) << "the previous report was changed";
  EXPECT_TRUE(temporaries(eval).empty()) << temporaries(eval).front();
  if (fs::exists(eval / "charts")) {
    EXPECT_TRUE(temporaries(eval / "charts").empty());
  }
}

// Images are read once, when the dataset loads: a dataset that disappears mid-run changes
// nothing, and the run makes the model it would have made.
TEST(Faults, ADatasetThatDisappearsMidRunChangesNothing) {
  const fs::path dir = test::scratch_dir("faults_dataset_gone");
  small_dataset(dir);
  auto r = test::run_command(train(dir, dir / "whole", "--iters 300"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // config.json is written once the data and any checkpoint are loaded; the images go then.
  const fs::path out = dir / "run";
  r = test::run_command("(" + train(dir, out, "--iters 300") + " & pid=$!; while [ ! -e " + (out / "config.json").string() +
                            " ]; do sleep 0.01; done; rm -rf " + (dir / "data").string() + "; wait $pid)",
                        dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(fs::exists(dir / "data"));
  EXPECT_TRUE(test::read_file(out / "model.ply") == test::read_file(dir / "whole" / "model.ply"));
}

// An output folder made read-only mid-run (a read-only bind mount, as root; otherwise its
// permissions): the next write is one clean error naming the file, and what was written
// before stays.
TEST(Faults, AnOutputFolderMadeReadOnlyMidRunIsACleanError) {
  const fs::path dir = test::scratch_dir("faults_read_only");
  small_dataset(dir);
  const fs::path out = dir / "run";
  fs::create_directories(out);
  const bool root = geteuid() == 0;
  const std::string protect = root ? "mount --bind -o ro " + out.string() + " " + out.string()
                                   : "chmod a-w " + out.string();
  const std::string unprotect = root ? "umount " + out.string() : "chmod u+w " + out.string();
  if (root && test::run_command(protect + " && " + unprotect, dir).exit_code != 0)
    GTEST_SKIP() << "this machine allows no read-only bind mount: " << test::read_file(dir / "stderr.txt");
  const auto r = test::run_command("(" + train(dir, out, "--iters 100000 --checkpoint-every 50") + " & pid=$!; while [ ! -e " +
                                       (out / "checkpoint.ckpt").string() + " ]; do sleep 0.01; done; " + protect +
                                       "; wait $pid; code=$?; " + unprotect + "; exit $code)",
                                   dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.err.rfind("error: " + out.string() + "/", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NO_THROW(test::split_checkpoint(test::read_file(out / "checkpoint.ckpt")));
  EXPECT_TRUE(temporaries(out).empty());
}

}  // namespace
}  // namespace splat
