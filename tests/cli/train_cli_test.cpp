// splat-train end to end on a tiny dataset rendered from the built-in demo model: it trains
// (loss down, PSNR up), writes the contract's outputs, is deterministic across thread counts,
// resumes exactly, saves on Ctrl-C, stops on divergence naming the group, rejects bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/cli_support.hpp"
#include "tests/data/dataset_test_folders.hpp"
#include "splat/data/dataset.hpp"
#include "splat/data/image_io.hpp"
#include "splat/data/transforms_json.hpp"
#include "splat/gaussians/ply_io.hpp"
#include "splat/train/nerf_training_config.hpp"
#include "splat/train/training_config.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

// 12 training and 3 test views of the demo model at 64x64, written once per test. ctest runs
// each test case as its own process, in parallel, so every test gets its own folder: a shared
// one would be deleted and rewritten under a running neighbour.
fs::path tiny_dataset() {
  static const fs::path dir = [] {
    const std::string test_name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    const fs::path d = test::scratch_dir("train_cli_dataset_" + test_name);
    test::write_demo_dataset(d, 12, 3, 64, 3000);
    // Small settings so the run takes about a second but still densifies and resets
    // (official), or warms up at half size, grows and prunes (compact, the default). The
    // schedule is not fitted to these short runs (a position step decayed within a few
    // hundred iterations leaves the random start where it is).
    test::write_text(d / "tiny_config.json", R"({"random_init_points": 4000, "densify_from_iter": 100,
      "densification_interval": 50, "opacity_reset_interval": 200, "densify_until_iter": 250,
      "compact_warmup_until": 60, "compact_grow_from": 100, "compact_grow_interval": 50,
      "compact_grow_until": 250, "compact_prune_window": 50, "schedule_follows_budget": false,
      "pose_refine_from": 50, "exposure_from": 50})");
    return d;
  }();
  return dir;
}

std::string train_command(const fs::path& out, const std::string& extra) {
  return std::string(SPLAT_TRAIN_EXE) + " --data " + tiny_dataset().string() + " --out " +
         out.string() + " --config " + (tiny_dataset() / "tiny_config.json").string() + " " + extra;
}

nlohmann::json read_json(const fs::path& file) { return nlohmann::json::parse(test::read_file(file)); }

// The NeRF on the same tiny dataset, with small networks and few samples so it runs in
// seconds (the structure is the default's: coarse + fine, occupancy grid after a warm-up).
// `lr_decay_iterations` sets where the parameter average starts (halfway).
std::string nerf_command(const fs::path& out, const std::string& extra, int lr_decay_iterations = 400) {
  const fs::path config = out.parent_path() / "nerf_config.json";
  test::write_text(config, R"({"rays_per_batch": 256, "occupancy_warmup": 100, "occupancy_interval": 10,
    "lr_init": 5e-3, "lr_final": 5e-4, "lr_decay_iterations": )" + std::to_string(lr_decay_iterations) + R"(,
    "model": {"coarse": {"depth": 2, "width": 32, "skip_layer": -1, "color_width": 16},
              "fine": {"depth": 2, "width": 32, "skip_layer": -1, "color_width": 16},
              "coarse_samples": 16, "fine_samples": 16,
              "box_min": [-2.5, -2.5, -2.5], "box_max": [2.5, 2.5, 2.5]}})");
  return std::string(SPLAT_TRAIN_EXE) + " --method nerf --data " + tiny_dataset().string() +
         " --out " + out.string() + " --config " + config.string() + " " + extra;
}

// The NGP preset with small tables and few samples, over the same tiny scene.
std::string ngp_command(const fs::path& out, const std::string& extra) {
  const fs::path config = out.parent_path() / "ngp_config.json";
  test::write_text(config, R"({"method": "ngp", "rays_per_batch": 256,
    "model": {"coarse": {"hash": {"levels": 4, "table_log2": 10, "max_resolution": 32}},
              "fine": {"hash": {"levels": 8, "table_log2": 12, "max_resolution": 64}},
              "coarse_samples": 16, "fine_samples": 8,
              "box_min": [-2.5, -2.5, -2.5], "box_max": [2.5, 2.5, 2.5]}})");
  return std::string(SPLAT_TRAIN_EXE) + " --method ngp --data " + tiny_dataset().string() + " --out " + out.string() +
         " --config " + config.string() + " " + extra;
}

TEST(TrainCli, TrainsAndWritesTheContractOutputs) {
  const fs::path dir = test::scratch_dir("train_cli_basic");
  const auto r = test::run_command(train_command(dir / "out", "--iters 300 --test-every 100"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const nlohmann::json m = read_json(dir / "out" / "metrics.json");
  EXPECT_EQ(m.at("method"), "splat");
  EXPECT_EQ(m.at("iterations").get<int>(), 300);
  EXPECT_GT(m.at("train_seconds").get<double>(), 0.0);
  EXPECT_EQ(m.at("test").at("views").get<int>(), 3);
  const auto& history = m.at("history");
  ASSERT_GE(history.size(), 3u);
  for (const auto& h : history)  // the contract's fields in every entry
    for (const char* key : {"iteration", "seconds", "loss", "num_gaussians"})
      EXPECT_TRUE(h.contains(key)) << key << " missing in " << h.dump();
  // The loss falls and the test PSNR rises.
  EXPECT_LT(history.back().at("loss").get<double>(), history.front().at("loss").get<double>() * 0.7);
  double first_psnr = 0;
  for (const auto& h : history)
    if (h.contains("test_psnr")) {
      first_psnr = h["test_psnr"];
      break;
    }
  EXPECT_GT(m.at("test").at("psnr").get<double>(), first_psnr + 1.0);
  EXPECT_GT(m.at("test").at("psnr").get<double>(), 18.0);
  // Every test point scores each test view by name; the mean of those is the test PSNR.
  for (const auto& h : history)
    if (h.contains("test_psnr")) {
      const auto& views = h.at("test_view_psnr");
      ASSERT_EQ(views.size(), 3u) << h.dump();
      double sum = 0;
      for (const auto& [name, psnr] : views.items()) sum += psnr.get<double>();
      EXPECT_NEAR(sum / 3, h.at("test_psnr").get<double>(), 1e-9) << h.dump();
    }
  EXPECT_EQ(m.at("test").at("view_psnr"), history.back().at("test_view_psnr"));
  // The appearance-fitted score (half_fitted_psnr.hpp) is reported beside it: on synthetic
  // views with fixed light, a fitted gain and offset gain a model little.
  const double fitted = m.at("test").at("half_fitted_psnr").get<double>();
  EXPECT_GT(fitted, 18.0);
  EXPECT_LT(std::abs(fitted - m.at("test").at("psnr").get<double>()), 5.0);
  // Time to quality: the first whole dB above the first score is listed, at a test point,
  // after the test point before it.
  std::vector<int> test_points;
  for (const auto& h : history)
    if (h.contains("test_psnr")) test_points.push_back(h.at("iteration").get<int>());
  const auto& levels = m.at("time_to_psnr");
  ASSERT_FALSE(levels.empty());
  EXPECT_EQ(levels.front().at("psnr").get<double>(), std::floor(first_psnr) + 1.0);
  for (const auto& level : levels) {
    EXPECT_NE(std::find(test_points.begin(), test_points.end(), level.at("iteration").get<int>()),
              test_points.end()) << level.dump();
    EXPECT_LT(level.at("after_seconds").get<double>(), level.at("seconds").get<double>()) << level.dump();
  }
  // The model file is a standard PLY of the reported size.
  const GaussianModel model = read_ply(dir / "out" / "model.ply");
  EXPECT_EQ(model.size(), m.at("num_gaussians").get<std::size_t>());
  EXPECT_EQ(model.sh_degree, 3);
  EXPECT_EQ(fs::file_size(dir / "out" / "model.ply"), m.at("model_bytes").get<std::size_t>());
  EXPECT_EQ(m.at("num_params").get<std::size_t>(), model.size() * 59);
  for (const char* name : {"view_000", "view_001", "view_002"})
    EXPECT_TRUE(fs::exists(dir / "out" / "test" / (std::string(name) + ".png"))) << name;
  EXPECT_TRUE(fs::exists(dir / "out" / "config.json"));
  for (const char* key : {"forward", "loss", "backward", "optimizer", "densify"})
    EXPECT_TRUE(m.at("ms_per_iteration").contains(key)) << key;
}

TEST(TrainCli, ResultDoesNotDependOnThreadCount) {
  for (const std::string strategy : {"compact", "official"}) {
    const fs::path dir = test::scratch_dir("train_cli_threads_" + strategy);
    for (const char* threads : {"1", "2"}) {
      const auto r = test::run_command(
          train_command(dir / threads, "--strategy " + strategy + " --iters 150 --quiet --threads " + threads), dir);
      ASSERT_EQ(r.exit_code, 0) << r.err;
    }
    EXPECT_TRUE(test::read_file(dir / "1" / "model.ply") == test::read_file(dir / "2" / "model.ply"))
        << strategy << ": models trained with 1 and 2 threads differ";
  }
}

TEST(TrainCli, ResumeContinuesExactly) {
  for (const std::string strategy : {"compact", "official"}) {
    const fs::path dir = test::scratch_dir("train_cli_resume_" + strategy);
    const std::string s = "--strategy " + strategy + " ";
    auto r = test::run_command(train_command(dir / "straight", s + "--iters 240 --quiet"), dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = test::run_command(train_command(dir / "split", s + "--iters 120 --checkpoint-every 120 --quiet"), dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    ASSERT_TRUE(fs::exists(dir / "split" / "checkpoint.ckpt"));
    r = test::run_command(
        train_command(dir / "split", s + "--iters 240 --quiet --resume " + (dir / "split").string()), dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(test::read_file(dir / "straight" / "model.ply") == test::read_file(dir / "split" / "model.ply"))
        << strategy << ": the resumed run's model differs from the uninterrupted run's";
    EXPECT_TRUE(fs::exists(dir / "straight" / "cameras_train.json")) << strategy;
  }
}

// The checkpoint fixes the run's settings: --resume continues that run (its strategy, its
// iteration budget when no --iters is given), an option that would change a setting it
// fixes is refused naming the option, the same value is no change, and the limits and
// intervals given are applied and recorded in config.json.
TEST(TrainCli, ResumeKeepsTheCheckpointsSettingsRefusesChangesAndTakesNewLimits) {
  const fs::path dir = test::scratch_dir("train_cli_resume_settings");
  const fs::path out = dir / "out";
  auto r = test::run_command(train_command(out, "--strategy official --iters 20 --checkpoint-every 20 --quiet"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string resume = " --quiet --resume " + out.string();
  // No --strategy and no --iters: the official run's 20 iterations, not the compact default's.
  r = test::run_command(train_command(out, resume), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_json(out / "metrics.json").at("iterations"), 20);
  EXPECT_EQ(read_json(out / "config.json").at("strategy"), "official");
  EXPECT_EQ(read_json(out / "config.json").at("iterations"), 20);
  const std::string model = test::read_file(out / "model.ply");
  // Options that change what the checkpoint fixes.
  for (const std::string& change : {std::string("--strategy compact"), std::string("--seed 3"),
                                    std::string("--bg black"), std::string("--max-gaussians 100")}) {
    r = test::run_command(train_command(out, change + resume), dir);
    EXPECT_EQ(r.exit_code, 2) << change;
    const std::string option = change.substr(0, change.find(' '));
    EXPECT_EQ(r.err.rfind("error: " + (out / "checkpoint.ckpt").string() + ": " + option + " sets ", 0), 0u)
        << change << ": " << r.err;
    EXPECT_NE(r.err.find("a resumed run keeps its settings"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(test::read_file(out / "model.ply") == model) << change << ": the refused run wrote a model";
  }
  // The same values are no change; new limits and intervals apply and are recorded.
  r = test::run_command(train_command(out, "--strategy official --seed 0 --iters 40 --test-every 20" + resume), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_json(out / "metrics.json").at("iterations"), 40);
  EXPECT_EQ(read_json(out / "config.json").at("iterations"), 40);
  EXPECT_EQ(read_json(out / "config.json").at("test_interval"), 20);
  // A limit below where the checkpoint is cannot be met.
  r = test::run_command(train_command(out, "--iters 30" + resume), dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--iters 30 is below the checkpoint's iteration 40"), std::string::npos) << r.err;
}

// Pruning by the share of views that draw a Gaussian keeps per-window counts of views: a
// checkpoint taken mid-window (windows of 16 views here) carries them, and older checkpoints,
// which lack them, need them only when a setting is on.
TEST(TrainCli, ResumeContinuesExactlyWithPruningByViewShare) {
  const fs::path dir = test::scratch_dir("train_cli_resume_view_share");
  nlohmann::json config = read_json(tiny_dataset() / "tiny_config.json");
  config["compact_prune_min_view_share"] = 0.3;
  config["compact_real_capture_only"] = false;  // the demo data has no point cloud
  test::write_text(dir / "config.json", config.dump());
  const auto command = [&](const fs::path& out, const std::string& extra) {
    return std::string(SPLAT_TRAIN_EXE) + " --data " + tiny_dataset().string() + " --out " + out.string() +
           " --config " + (dir / "config.json").string() + " --quiet " + extra;
  };
  auto r = test::run_command(command(dir / "straight", "--iters 240"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = test::run_command(train_command(dir / "plain", "--iters 240 --quiet"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_LT(read_json(dir / "straight" / "metrics.json").at("num_gaussians").get<int>(),
            read_json(dir / "plain" / "metrics.json").at("num_gaussians").get<int>())
      << "the view share pruned nothing";
  r = test::run_command(command(dir / "split", "--iters 120 --checkpoint-every 120"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = test::run_command(command(dir / "split", "--iters 240 --resume " + (dir / "split").string()), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(test::read_file(dir / "straight" / "model.ply") == test::read_file(dir / "split" / "model.ply"))
      << "the resumed run's model differs from the uninterrupted run's";
}

// --batch B: a step trains on B views and the iterations still count views; a run split by a
// checkpoint is the same run.
TEST(TrainCli, BatchesOfViewsCountIterationsInViewsAndResumeExactly) {
  const fs::path dir = test::scratch_dir("train_cli_batch");
  auto r = test::run_command(train_command(dir / "straight", "--batch 4 --iters 240 --test-every 0 --quiet"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json m = read_json(dir / "straight" / "metrics.json");
  EXPECT_EQ(m.at("iterations").get<int>(), 240);
  std::vector<int> history;
  for (const auto& h : m.at("history")) history.push_back(h.at("iteration").get<int>());
  EXPECT_EQ(history, (std::vector<int>{100, 200, 240}));  // the steps ending at 100, 200, the end
  EXPECT_EQ(read_json(dir / "straight" / "config.json").at("batch"), 4);
  r = test::run_command(train_command(dir / "split", "--batch 4 --iters 120 --checkpoint-every 120 --test-every 0 --quiet"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = test::run_command(
      train_command(dir / "split", "--batch 4 --iters 240 --test-every 0 --quiet --resume " + (dir / "split").string()), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(test::read_file(dir / "straight" / "model.ply") == test::read_file(dir / "split" / "model.ply"))
      << "the resumed batch run's model differs from the uninterrupted one's";
  // A batch of 1 is one view per step: a different run from batches of 4.
  r = test::run_command(train_command(dir / "one", "--iters 240 --test-every 0 --quiet"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(test::read_file(dir / "straight" / "model.ply") == test::read_file(dir / "one" / "model.ply"));

  r = test::run_command(train_command(dir / "bad", "--batch 3 --iters 100 --quiet"), dir);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("must be a multiple of \"batch\" (--batch, 3)"), std::string::npos) << r.err;
  r = test::run_command(nerf_command(dir / "nerf", "--batch 2 --iters 10 --quiet"), dir);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--batch is a splat setting"), std::string::npos) << r.err;
}

#ifdef SPLAT_MPIEXEC
// mpirun with K ranks on this machine: as root too (CI), more ranks than cores allowed, and
// no binding (each rank sets its own thread count). Leak checks are off in the ranks of the
// sanitizer suite: Open MPI's plugins hold allocations to the end, unloaded by then, so
// LeakSanitizer cannot tell them from ours; the same trainer code runs with leak checks in
// the single-process tests.
std::string mpirun(int ranks) {
  return "env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 ASAN_OPTIONS=detect_leaks=0 " +
         std::string(SPLAT_MPIEXEC) +
         " -np " + std::to_string(ranks) + " --oversubscribe --bind-to none ";
}
#endif

// Data-parallel training: two ranks of one thread each, and four (oversubscribed), train at
// the same --batch the model one process of two threads trains, byte for byte; rank 0 alone
// writes and reports.
TEST(TrainCli, TwoMpiRanksTrainTheModelOneProcessTrains) {
#ifndef SPLAT_MPIEXEC
  GTEST_SKIP() << "built without MPI (SPLAT_MPI=OFF, or no MPI library found): no mpirun to run";
#else
  const fs::path dir = test::scratch_dir("train_cli_mpi");
  const std::string common = "--batch 4 --iters 160 --test-every 80 --checkpoint-every 80 ";
  auto r = test::run_command(train_command(dir / "one", common + "--threads 2 --quiet"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json one = read_json(dir / "one" / "metrics.json");
  EXPECT_EQ(one.at("ranks"), 1);
  EXPECT_FALSE(one.contains("exchange"));
  for (const int ranks : {2, 4}) {
    const fs::path out = dir / ("ranks" + std::to_string(ranks));
    r = test::run_command(mpirun(ranks) + train_command(out, common + "--threads 1"), dir);
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    EXPECT_TRUE(test::read_file(dir / "one" / "model.ply") == test::read_file(out / "model.ply"))
        << ranks << " ranks trained a different model from 1 process";
    EXPECT_TRUE(test::read_file(dir / "one" / "checkpoint.ckpt") == test::read_file(out / "checkpoint.ckpt"));
    const nlohmann::json several = read_json(out / "metrics.json");
    EXPECT_EQ(several.at("ranks"), ranks);
    EXPECT_EQ(several.at("test"), one.at("test"));
    EXPECT_EQ(several.at("history").size(), one.at("history").size());
    // Only rank 0 reported: one "done" line.
    std::size_t done = 0;
    for (std::size_t at = r.out.find("done: "); at != std::string::npos; at = r.out.find("done: ", at + 1)) ++done;
    EXPECT_EQ(done, 1u) << r.out;
    EXPECT_NE(several.at("ms_per_iteration").find("exchange"), several.at("ms_per_iteration").end());
    const nlohmann::json& exchange = several.at("exchange");
    EXPECT_GT(exchange.at("megabytes_sent").get<double>(), 0.0);
    const double block = exchange.at("rows_drawn_in_block"), batch = exchange.at("rows_drawn_in_batch");
    EXPECT_GT(block, 0.0);
    EXPECT_LE(block, batch);
    EXPECT_LE(batch, 1.0);
  }

  // Batches that would make the model depend on the rank count are refused, naming why.
  r = test::run_command(mpirun(2) + train_command(dir / "odd", "--batch 3 --iters 30 --quiet --threads 1"), dir);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("power of two"), std::string::npos) << r.err;
  r = test::run_command(mpirun(2) + nerf_command(dir / "nerf", "--iters 10 --quiet --threads 1"), dir);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("the NeRF trains in one process"), std::string::npos) << r.err;
#endif
}

// A rank killed mid-run ends the run on every rank within seconds, the launcher naming the
// rank, and the last checkpoint resumes.
TEST(TrainCli, AKilledMpiRankEndsTheRunAndTheCheckpointResumes) {
#ifndef SPLAT_MPIEXEC
  GTEST_SKIP() << "built without MPI (SPLAT_MPI=OFF, or no MPI library found): no mpirun to run";
#else
  const fs::path dir = test::scratch_dir("train_cli_mpi_kill");
  const fs::path out = dir / "out";
  std::string script = "(";
  script.append(mpirun(2))
      .append(train_command(out, "--batch 2 --iters 1000000 --checkpoint-every 20 --test-every 0 --quiet --threads 1"))
      .append(" > " + (dir / "log").string() + " 2>&1 & launcher=$!; ")
      .append("for i in $(seq 1 600); do [ -f " + (out / "checkpoint.ckpt").string() + " ] && break; sleep 0.1; done; ")
      // Rank 1: the process whose environment says so.
      .append("for p in $(pgrep -f " + out.string() + "); do ")
      .append("if tr '\\0' '\\n' < /proc/$p/environ 2>/dev/null | grep -qx OMPI_COMM_WORLD_RANK=1; then kill -9 $p; fi; done; ")
      .append("start=$(date +%s%N); wait $launcher; echo $? > " + (dir / "code").string() + "; ")
      .append("echo $(( ($(date +%s%N) - start) / 1000000 )) > " + (dir / "ms").string() + ")");
  test::run_command(script, dir);
  EXPECT_NE(std::stoi(test::read_file(dir / "code")), 0);
  EXPECT_LT(std::stoi(test::read_file(dir / "ms")), 20000) << "the other rank did not end within 20 s";
  const std::string log = test::read_file(dir / "log");
  EXPECT_NE(log.find("rank 1"), std::string::npos) << log;
  ASSERT_TRUE(fs::exists(out / "checkpoint.ckpt"));
  const auto r = test::run_command(
      mpirun(2) + train_command(out, "--batch 2 --iters 1000000 --max-seconds 2 --test-every 0 --quiet --threads 1 "
                                     "--resume " + out.string()), dir);
  EXPECT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_GT(read_json(out / "metrics.json").at("iterations").get<int>(), 20);
#endif
}

// Under pose refinement metrics.json also scores the test views at their recorded poses
// (carried into the model's frame, not aligned): with no alignment steps, exactly the test
// score, though the training poses moved.
TEST(TrainCli, PoseRefinementReportsTheTestScoreAtTheRecordedPoses) {
  const fs::path dir = test::scratch_dir("train_cli_refine_poses_recorded");
  nlohmann::json config = read_json(tiny_dataset() / "tiny_config.json");
  config["test_pose_alignment_steps"] = 0;
  test::write_text(dir / "config.json", config.dump());
  auto r = test::run_command(std::string(SPLAT_TRAIN_EXE) + " --data " + tiny_dataset().string() + " --out " +
                                 (dir / "out").string() + " --config " + (dir / "config.json").string() +
                                 " --refine-poses --iters 120 --test-every 0 --quiet",
                             dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json m = read_json(dir / "out" / "metrics.json");
  EXPECT_GT(m["pose_refinement"]["mean_rotation_correction_deg"].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(m["pose_refinement"]["test_psnr_at_recorded_poses"].get<double>(), m["test"]["psnr"].get<double>());
}

// Pose refinement: the corrections are part of the run's state (a resumed run is the same
// run, whatever the thread count), and metrics.json says how the test views were scored.
TEST(TrainCli, PoseRefinementAndExposureMapsResumeExactlyAndReportTheirProtocol) {
  const fs::path dir = test::scratch_dir("train_cli_refine_poses");
  const std::string s = "--refine-poses --exposure-compensation --test-every 60 ";
  auto r = test::run_command(train_command(dir / "straight", s + "--iters 240 --quiet --threads 2"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = test::run_command(train_command(dir / "split", s + "--iters 120 --checkpoint-every 120 --quiet --threads 1"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = test::run_command(
      train_command(dir / "split", s + "--iters 240 --quiet --threads 2 --resume " + (dir / "split").string()), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(test::read_file(dir / "straight" / "model.ply") == test::read_file(dir / "split" / "model.ply"))
      << "the resumed run's model differs from the uninterrupted run's";
  const nlohmann::json m = read_json(dir / "straight" / "metrics.json");
  // The test views' alignments carry over too: the resumed run scores as the straight one.
  EXPECT_EQ(m["test"]["psnr"], read_json(dir / "split" / "metrics.json")["test"]["psnr"]);
  ASSERT_TRUE(m.contains("pose_refinement")) << m.dump();
  EXPECT_EQ(m["pose_refinement"]["training_views"], 12);
  EXPECT_GT(m["pose_refinement"]["mean_rotation_correction_deg"].get<double>(), 0.0);  // it moved
  EXPECT_NE(m["pose_refinement"]["test_protocol"].get<std::string>().find("aligned"), std::string::npos);
  EXPECT_TRUE(m["pose_refinement"]["test_psnr_at_recorded_poses"].is_number()) << m.dump();
  EXPECT_EQ(read_json(dir / "straight" / "config.json")["refine_poses"], true);
  // The training views' poses as trained, one frame per view, readable as cameras.
  const std::vector<CameraFrame> trained = load_transforms(dir / "straight" / "cameras_train.json");
  ASSERT_EQ(trained.size(), 12u);
  const std::vector<CameraFrame> recorded = load_transforms(tiny_dataset() / "transforms_train.json");
  double moved = 0;
  for (std::size_t i = 0; i < trained.size(); ++i)
    moved = std::max(moved, double(glm::length(trained[i].camera.camera_from_world_translation -
                                               recorded[i].camera.camera_from_world_translation)));
  EXPECT_GT(moved, 0.0);
  ASSERT_TRUE(m.contains("exposure_compensation")) << m.dump();
  EXPECT_GT(m["exposure_compensation"]["max_abs_log_gain"].get<double>(), 0.0);  // the maps moved
  EXPECT_NE(m["exposure_compensation"]["test_protocol"].get<std::string>().find("without"), std::string::npos);
  EXPECT_EQ(read_json(dir / "straight" / "config.json")["exposure_compensation"], true);
  // A later run without refinement in the same folder leaves its own training cameras: the recorded ones.
  r = test::run_command(train_command(dir / "straight", "--iters 20 --test-every 0 --quiet"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<CameraFrame> unrefined = load_transforms(dir / "straight" / "cameras_train.json");
  ASSERT_EQ(unrefined.size(), recorded.size());
  for (std::size_t i = 0; i < unrefined.size(); ++i)
    EXPECT_LT(glm::length(unrefined[i].camera.camera_from_world_translation -
                          recorded[i].camera.camera_from_world_translation),
              1e-5f);
  // The NeRF has no poses to refine.
  r = test::run_command(std::string(SPLAT_TRAIN_EXE) + " --data " + tiny_dataset().string() + " --out " +
                            (dir / "nerf").string() + " --method nerf --refine-poses --iters 1",
                        dir);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--refine-poses"), std::string::npos) << r.err;
  r = test::run_command(std::string(SPLAT_TRAIN_EXE) + " --data " + tiny_dataset().string() + " --out " +
                            (dir / "nerf").string() + " --method nerf --exposure-compensation --iters 1",
                        dir);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--exposure-compensation"), std::string::npos) << r.err;
}

// Without a span in the config, the schedule spans the run's --iters, recorded in
// config.json; extending the run with --resume keeps it (the run goes on at the schedule's end).
TEST(TrainCli, ScheduleSpansTheRunAndIsKeptOnResume) {
  const fs::path dir = test::scratch_dir("train_cli_schedule_span");
  nlohmann::json config = read_json(tiny_dataset() / "tiny_config.json");
  config["schedule_follows_budget"] = true;
  test::write_text(dir / "config.json", config.dump());
  const std::string base = std::string(SPLAT_TRAIN_EXE) + " --data " + tiny_dataset().string() + " --out " +
                           (dir / "out").string() + " --config " + (dir / "config.json").string() + " --quiet ";
  auto r = test::run_command(base + "--iters 60 --checkpoint-every 60", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_json(dir / "out" / "config.json").at("schedule_iterations"), 60);
  r = test::run_command(base + "--iters 90 --resume " + (dir / "out").string(), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json resumed = read_json(dir / "out" / "config.json");
  EXPECT_EQ(resumed.at("schedule_iterations"), 60);
  EXPECT_EQ(resumed.at("iterations"), 90);
}

// Every run leaves the views it trained and tested on as transforms files, whatever the input
// format: from a COLMAP capture at --downscale 2, the cameras as loaded (intrinsics at half
// size, one camera per image where they differ), each frame named as its view, and
// splat-render renders the test views from them under those names. --holdout-every chooses
// the test views.
TEST(TrainCli, WritesTheViewsItTrainedAndTestedOnAsTransformsFilesAndHoldsOutWhatItIsTold) {
  const fs::path dir = test::scratch_dir("train_cli_view_cameras");
  test::TestModel model;
  model.cameras = {{1, ColmapCameraModel::kPinhole, 24, 18, {22.0, 22.0, 12.0, 9.0}},
                   {2, ColmapCameraModel::kPinhole, 24, 18, {26.0, 25.0, 11.0, 9.5}}};
  for (int i = 0; i < 10; ++i) {
    ColmapImage image;
    image.id = std::uint32_t(1 + i);
    const double angle = 0.1 * (i - 5);  // an arc 4 units out, facing in
    image.quaternion = {std::cos(angle / 2), 0.0, std::sin(angle / 2), 0.0};
    image.translation = {0.1 * i, -0.05 * i, 4.0};
    image.camera_id = std::uint32_t(1 + i % 2);
    image.name = "shot_" + std::to_string(i) + ".png";
    model.images.push_back(image);
  }
  for (int i = 0; i < 100; ++i) model.points.push_back({{0.2 * (i % 10) - 0.9, 0.2 * (i / 10) - 0.9, 0.0}, {90, 60, 30}});
  test::write_colmap_folder(dir / "capture", model, test::ModelForm::kText);
  for (const ColmapImage& image : model.images)
    write_png(Image(24, 18, 3, 0.4f), dir / "capture" / "images" / image.name);
  auto r = test::run_command(std::string(SPLAT_TRAIN_EXE) + " --data " + (dir / "capture").string() + " --out " +
                                 (dir / "out").string() + " --downscale 2 --iters 20 --quiet",
                             dir);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  DatasetOptions options;
  options.downscale = 2;
  const Dataset dataset = load_dataset(dir / "capture", options);
  ASSERT_FALSE(dataset.test.empty());
  const auto expect_cameras_of = [](const fs::path& file, const std::vector<DatasetView>& views) {
    const std::vector<CameraFrame> frames = load_transforms(file);
    ASSERT_EQ(frames.size(), views.size()) << file;
    for (std::size_t i = 0; i < frames.size(); ++i) {
      const Camera &written = frames[i].camera, &loaded = views[i].camera;
      EXPECT_EQ(frames[i].name, views[i].name);
      EXPECT_EQ(written.width, loaded.width);
      EXPECT_EQ(written.height, loaded.height);
      EXPECT_FLOAT_EQ(written.fx, loaded.fx);
      EXPECT_FLOAT_EQ(written.fy, loaded.fy);
      EXPECT_FLOAT_EQ(written.cx, loaded.cx);
      EXPECT_FLOAT_EQ(written.cy, loaded.cy);
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(written.camera_from_world_translation[c], loaded.camera_from_world_translation[c], 1e-5f);
        for (int k = 0; k < 3; ++k)
          EXPECT_NEAR(written.camera_from_world_rotation[c][k], loaded.camera_from_world_rotation[c][k], 1e-6f);
      }
    }
  };
  expect_cameras_of(dir / "out" / "cameras_train.json", dataset.train);
  expect_cameras_of(dir / "out" / "cameras_test.json", dataset.test);
  EXPECT_NE(dataset.train[0].camera.fx, dataset.train[1].camera.fx);  // two cameras, both kept
  r = test::run_command(std::string(SPLAT_RENDER_EXE) + " --model " + (dir / "out" / "model.ply").string() +
                            " --cameras " + (dir / "out" / "cameras_test.json").string() + " --out " +
                            (dir / "renders").string(),
                        dir);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  for (const DatasetView& view : dataset.test) {
    const Image render = read_image(dir / "renders" / (view.name + ".png"));
    EXPECT_EQ(render.width, view.camera.width) << view.name;
    EXPECT_EQ(render.height, view.camera.height) << view.name;
  }

  // --holdout-every 0: every view trains, nothing is scored, and no test file is left behind
  // (the folder's earlier run wrote one).
  r = test::run_command(std::string(SPLAT_TRAIN_EXE) + " --data " + (dir / "capture").string() + " --out " +
                            (dir / "out").string() + " --downscale 2 --iters 20 --holdout-every 0",
                        dir);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("no test views: nothing scored"), std::string::npos) << r.out;
  const nlohmann::json m = read_json(dir / "out" / "metrics.json");
  EXPECT_FALSE(m.contains("test")) << m.dump();
  for (const nlohmann::json& entry : m.at("history")) EXPECT_FALSE(entry.contains("test_psnr"));
  EXPECT_EQ(load_transforms(dir / "out" / "cameras_train.json").size(), 10u);
  EXPECT_FALSE(fs::exists(dir / "out" / "cameras_test.json"));
  r = test::run_command(std::string(SPLAT_TRAIN_EXE) + " --data " + (dir / "capture").string() + " --out " +
                            (dir / "bad").string() + " --holdout-every -1",
                        dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("option --holdout-every must be a whole number from 0 to"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "bad"));
}

// A COLMAP capture whose held-out views disagree with every other: the training photographs
// are white as the background is, the validation ones dark, as are the points. The views are
// on an arc, three of them (img_14, img_22, img_27) next to a view taken from almost the same
// place: the holdout takes those three, the most redundant. Training fades the model, so the validation score
// falls from its first point on: the run stops where the holdout decides and keeps the model
// of its best score, and says so.
TEST(TrainCli, AFallingValidationScoreStopsTrainingOnTheBestModel) {
  const fs::path dir = test::scratch_dir("train_cli_validation");
  test::TestModel model;
  model.cameras = {{1, ColmapCameraModel::kPinhole, 24, 18, {22.0, 22.0, 12.0, 9.0}}};
  for (int i = 0; i < 20; ++i) {
    ColmapImage image;
    image.id = std::uint32_t(1 + i);
    const bool beside_previous = i == 5 || i == 13 || i == 18;
    const double angle = beside_previous ? 0.08 * (i - 11) + 0.005 : 0.08 * (i - 10);  // an arc 4 units out, facing in
    image.quaternion = {std::cos(angle / 2), 0.0, std::sin(angle / 2), 0.0};
    image.translation = {0.0, 0.0, 4.0};
    image.camera_id = 1;
    image.name = "img_" + std::to_string(10 + i) + ".png";
    model.images.push_back(image);
  }
  for (int i = 0; i < 200; ++i)  // a 10 × 10 × 2 grid filling the middle of every view
    model.points.push_back({{0.2 * (i % 10) - 0.9, 0.2 * (i / 10 % 10) - 0.9, 0.2 * (i / 100)}, {25, 25, 25}});
  test::write_colmap_folder(dir / "capture", model, test::ModelForm::kText);
  for (const ColmapImage& image : model.images) {
    const bool held_out = image.name == "img_14.png" || image.name == "img_22.png" || image.name == "img_27.png";
    write_png(Image(24, 18, 3, held_out ? 0.1f : 1.0f), dir / "capture" / "images" / image.name);
  }
  test::write_text(dir / "config.json", R"({"strategy": "official", "position_lr_max_steps": 60,
    "validation_every": 8, "validation_interval": 5, "validation_decide_at": 0.5})");
  const auto r = test::run_command(std::string(SPLAT_TRAIN_EXE) + " --data " + (dir / "capture").string() +
                                       " --out " + (dir / "out").string() + " --config " +
                                       (dir / "config.json").string() + " --iters 60",
                                   dir);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const nlohmann::json m = read_json(dir / "out" / "metrics.json");
  EXPECT_EQ(m.at("stopped_by"), "validation");
  EXPECT_EQ(m.at("iterations"), 34);  // the first score past half of the 60-iteration schedule
  const nlohmann::json& v = m.at("validation");
  EXPECT_EQ(v.at("views"), nlohmann::json({"img_14", "img_22", "img_27"}));
  EXPECT_EQ(v.at("decision"), "restored");
  EXPECT_EQ(v.at("best").at("iteration"), 4);
  EXPECT_EQ(v.at("scores").size(), 7u);  // after 4, 9, ..., 34 (before the steps holding 5, 10, ...)
  EXPECT_NE(r.out.find("validation: the held-out views fell "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("training stopped on the model of iteration 4"), std::string::npos) << r.out;
}

// Both strategies for the same iterations on the tiny scene, their schedules scaled down
// alike: the compact model is smaller and no worse. Iteration-limited, so machine load
// cannot change the outcome.
TEST(TrainCli, CompactEndsSmallerThanOfficialAtEqualOrBetterPsnr) {
  const fs::path dir = test::scratch_dir("train_cli_compact_vs_official");
  nlohmann::json metrics[2];
  const char* strategies[] = {"compact", "official"};
  for (int i = 0; i < 2; ++i) {
    const auto r = test::run_command(
        train_command(dir / strategies[i], std::string("--strategy ") + strategies[i] + " --iters 600 --quiet"), dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    metrics[i] = read_json(dir / strategies[i] / "metrics.json");
    EXPECT_EQ(metrics[i].at("strategy"), strategies[i]);
    EXPECT_EQ(read_json(dir / strategies[i] / "config.json").at("strategy"), strategies[i]);
  }
  const auto count = [](const nlohmann::json& m) { return m.at("num_gaussians").get<std::size_t>(); };
  const auto psnr = [](const nlohmann::json& m) { return m.at("test").at("psnr").get<double>(); };
  EXPECT_LT(count(metrics[0]), count(metrics[1]));
  EXPECT_GE(psnr(metrics[0]), psnr(metrics[1]));
  std::printf("compact %zu Gaussians %.3f dB, official %zu Gaussians %.3f dB\n", count(metrics[0]),
              psnr(metrics[0]), count(metrics[1]), psnr(metrics[1]));
}

// --max-gaussians is a hard cap for both strategies: no history entry ever exceeds it.
TEST(TrainCli, GaussianCapIsNeverExceeded) {
  for (const std::string strategy : {"compact", "official"}) {
    const fs::path dir = test::scratch_dir("train_cli_cap_" + strategy);
    const auto r = test::run_command(
        train_command(dir / "out", "--strategy " + strategy + " --iters 300 --max-gaussians 1500 --quiet"), dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json m = read_json(dir / "out" / "metrics.json");
    std::size_t largest = 0;
    for (const auto& h : m.at("history")) largest = std::max(largest, h.at("num_gaussians").get<std::size_t>());
    EXPECT_LE(largest, 1500u) << strategy;
    EXPECT_GT(largest, 1000u) << strategy << ": the cap was meant to bind";
  }
}

TEST(TrainCli, InterruptSavesCheckpointAndModel) {
  const fs::path dir = test::scratch_dir("train_cli_interrupt");
  // Built with append: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string.
  std::string cmd = "(";
  cmd.append(train_command(dir / "out", "--iters 1000000 --quiet"))
      .append(" & pid=$!; sleep 2; kill -INT $pid; wait $pid; echo $? > ")
      .append((dir / "code").string())
      .append(")");
  test::run_command(cmd, dir);
  EXPECT_EQ(std::stoi(test::read_file(dir / "code")), 130);
  EXPECT_TRUE(fs::exists(dir / "out" / "checkpoint.ckpt"));
  const GaussianModel model = read_ply(dir / "out" / "model.ply");
  EXPECT_GT(model.size(), 0u);
  EXPECT_EQ(read_json(dir / "out" / "metrics.json").at("stopped_by"), "interrupt");
}

TEST(TrainCli, DivergenceStopsNamingIterationAndGroup) {
  const fs::path dir = test::scratch_dir("train_cli_diverge");
  // No setting within its limits makes this training blow up, so a mean is made NaN after
  // step 20 (the fault-injection hook); the divergence check must find it as a real one.
  test::write_text(dir / "explode.json", R"({"random_init_points": 2000})");
  const auto r = test::run_command("SPLAT_FAULT_NAN_AT_ITERATION=20 " + std::string(SPLAT_TRAIN_EXE) + " --data " + tiny_dataset().string() +
                                       " --out " + (dir / "out").string() + " --iters 50 --quiet --config " +
                                       (dir / "explode.json").string(),
                                   dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("diverged at iteration"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("non-finite means"), std::string::npos) << r.err;
  const GaussianModel last_good = read_ply(dir / "out" / "model.ply");  // finite, readable
  EXPECT_GT(last_good.size(), 0u);
}

TEST(TrainCli, BadInputsFailCleanly) {
  const fs::path dir = test::scratch_dir("train_cli_bad");
  fs::create_directories(dir / "empty");
  const std::string exe = SPLAT_TRAIN_EXE;
  struct Case { std::string args, expected; };
  const Case cases[] = {
      {"--data /nonexistent --out " + (dir / "o").string(), "/nonexistent"},
      {"--data " + (dir / "empty").string() + " --out " + (dir / "o").string(), (dir / "empty").string()},
      {"--data " + tiny_dataset().string() + " --out " + (dir / "o").string() + " --iters 0", "--iters"},
      {"--data " + tiny_dataset().string() + " --out " + (dir / "o").string() + " --bg green", "--bg"},
      {"--data " + tiny_dataset().string() + " --out " + (dir / "o").string() + " --strategy greedy", "greedy"},
      {"--data " + tiny_dataset().string() + " --out " + (dir / "o").string() + " --resume /nonexistent.ckpt", "/nonexistent.ckpt"},
      {"--out " + (dir / "o").string(), "--data"},
  };
  for (const Case& c : cases) {
    const auto r = test::run_command(exe + " " + c.args + " --quiet", dir);
    EXPECT_EQ(r.exit_code, 2) << c.args;
    EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(c.expected), std::string::npos) << c.args << " -> " << r.err;
  }
}

}  // namespace
}  // namespace splat

namespace splat {
namespace {

// A NeRF run in dir/out: the loss falls and the test PSNR rises between the history's first
// and last points, and splat-render draws from `model_name` exactly what the trainer's test
// render shows.
void expect_learns_and_renders(const fs::path& dir, const std::string& model_name) {
  const nlohmann::json m = read_json(dir / "out" / "metrics.json");
  const auto& history = m.at("history");
  EXPECT_LT(history.back().at("loss").get<double>(), 0.6 * history.front().at("loss").get<double>());
  double first_psnr = 0;
  for (const auto& h : history)
    if (h.contains("test_psnr")) {
      first_psnr = h.at("test_psnr").get<double>();
      break;
    }
  EXPECT_GT(m.at("test").at("psnr").get<double>(), first_psnr + 0.2);
  const auto render = test::run_command(std::string(SPLAT_RENDER_EXE) + " --model " +
                                            (dir / "out" / model_name).string() + " --cameras " +
                                            (tiny_dataset() / "transforms_test.json").string() +
                                            " --bg 1,1,1 --out " + (dir / "render").string(),
                                        dir);
  ASSERT_EQ(render.exit_code, 0) << render.err;
  EXPECT_TRUE(test::read_file(dir / "render" / "view_000.png") ==
              test::read_file(dir / "out" / "test" / "view_000.png"));
}

TEST(TrainCli, NerfTrainsAndWritesTheContractOutputs) {
  const fs::path dir = test::scratch_dir("train_cli_nerf");
  const auto r = test::run_command(nerf_command(dir / "out", "--iters 600 --test-every 100 --quiet"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const nlohmann::json m = read_json(dir / "out" / "metrics.json");
  EXPECT_EQ(m.at("method"), "nerf");
  EXPECT_EQ(m.at("iterations").get<int>(), 600);
  EXPECT_GT(m.at("num_params").get<long>(), 0);
  EXPECT_EQ(m.at("model_bytes").get<std::uintmax_t>(), fs::file_size(dir / "out" / "model.nerf"));
  ASSERT_GE(m.at("history").size(), 4u);
  // (The test views look from another elevation than the 12 training views, which a NeRF
  // this small and this short generalises to only roughly: hence the modest bars. From its
  // nearly transparent start the field has drawn 10.0 → 10.26 dB by iteration 600.)
  expect_learns_and_renders(dir, "model.nerf");
  for (const char* view : {"view_000", "view_001", "view_002"})
    EXPECT_TRUE(fs::exists(dir / "out" / "test" / (std::string(view) + ".png"))) << view;
}

TEST(TrainCli, NerfResultDoesNotDependOnThreadCount) {
  const fs::path dir = test::scratch_dir("train_cli_nerf_threads");
  for (const char* threads : {"1", "2"}) {
    fs::create_directories(dir / threads);
    const auto r = test::run_command(
        nerf_command(dir / threads / "out", std::string("--iters 120 --test-every 0 --quiet --threads ") + threads), dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  EXPECT_TRUE(test::read_file(dir / "1" / "out" / "model.nerf") == test::read_file(dir / "2" / "out" / "model.nerf"))
      << "NeRF models trained with 1 and 2 threads differ";
}

TEST(TrainCli, NerfResumeContinuesExactly) {
  const fs::path dir = test::scratch_dir("train_cli_nerf_resume");
  // The rate decays over 100 iterations: the average runs from 50 on, so the checkpoint at 80
  // carries it.
  auto r = test::run_command(nerf_command(dir / "straight", "--iters 160 --test-every 0 --quiet", 100), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = test::run_command(nerf_command(dir / "split", "--iters 80 --checkpoint-every 80 --test-every 0 --quiet", 100),
                        dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = test::run_command(
      nerf_command(dir / "split", "--iters 160 --test-every 0 --quiet --resume " + (dir / "split").string(), 100), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(test::read_file(dir / "straight" / "model.nerf") == test::read_file(dir / "split" / "model.nerf"))
      << "the resumed NeRF differs from the uninterrupted one";
}

TEST(TrainCli, NerfDivergenceStopsNamingIterationAndGroupKeepingAGoodModel) {
  const fs::path dir = test::scratch_dir("train_cli_nerf_diverge");
  // A fine-network weight made NaN after step 20 (the fault-injection hook).
  test::write_text(dir / "explode.json", R"({"rays_per_batch": 64,
    "model": {"coarse": {"depth": 2, "width": 16, "skip_layer": -1, "color_width": 8},
              "fine": {"depth": 2, "width": 16, "skip_layer": -1, "color_width": 8},
              "coarse_samples": 8, "fine_samples": 8}})");
  const auto r = test::run_command("SPLAT_FAULT_NAN_AT_ITERATION=20 " + std::string(SPLAT_TRAIN_EXE) + " --method nerf --data " +
                                       tiny_dataset().string() + " --out " + (dir / "out").string() +
                                       " --iters 50 --quiet --config " + (dir / "explode.json").string(),
                                   dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("diverged at iteration"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("non-finite"), std::string::npos) << r.err;
  const nlohmann::json m = read_json(dir / "out" / "metrics.json");
  EXPECT_EQ(m.at("stopped_by"), "diverged");
  EXPECT_GT(m.at("diverged").at("iteration").get<int>(), 0);
  // The last good model is kept and renders.
  const auto render = test::run_command(std::string(SPLAT_RENDER_EXE) + " --model " +
                                            (dir / "out" / "model.nerf").string() + " --cameras " +
                                            (tiny_dataset() / "transforms_test.json").string() +
                                            " --width 16 --height 16 --out " + (dir / "render").string(),
                                        dir);
  EXPECT_EQ(render.exit_code, 0) << render.err;
}

TEST(TrainCli, NerfRejectsSplatOnlyOptionsAndBadModels) {
  const fs::path dir = test::scratch_dir("train_cli_nerf_bad");
  auto r = test::run_command(nerf_command(dir / "out", "--iters 10 --max-gaussians 100"), dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--max-gaussians"), std::string::npos) << r.err;
  test::write_text(dir / "broken.nerf", "SPLATNRF but then nothing sensible");
  r = test::run_command(std::string(SPLAT_RENDER_EXE) + " --model " + (dir / "broken.nerf").string() +
                            " --cameras " + (tiny_dataset() / "transforms_test.json").string() +
                            " --out " + (dir / "render").string(),
                        dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("broken.nerf"), std::string::npos) << r.err;
}

TEST(TrainCli, NgpTrainsWritesModelNgpAndRendersIt) {
  const fs::path dir = test::scratch_dir("train_cli_ngp");
  const auto r = test::run_command(ngp_command(dir / "out", "--iters 300 --test-every 100 --quiet"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const nlohmann::json m = read_json(dir / "out" / "metrics.json");
  EXPECT_EQ(m.at("method"), "ngp");
  EXPECT_EQ(read_json(dir / "out" / "config.json").at("method"), "ngp");
  EXPECT_EQ(m.at("model_bytes").get<std::uintmax_t>(), fs::file_size(dir / "out" / "model.ngp"));
  EXPECT_FALSE(fs::exists(dir / "out" / "model.nerf"));
  EXPECT_EQ(test::read_file(dir / "out" / "model.ngp").substr(0, 8), "SPLATNGP");
  ASSERT_GE(m.at("history").size(), 3u);
  expect_learns_and_renders(dir, "model.ngp");
  // What a step evaluated: the config's 256 rays; at most 16 coarse samples per ray, and the
  // fine pass at most the coarse ones and 8 more; some of each, and the grid skipping others
  // once it has learnt where the object is not.
  const nlohmann::json& samples = m.at("samples_per_iteration");
  EXPECT_EQ(samples.at("rays").get<double>(), 256.0);
  EXPECT_GT(samples.at("coarse").get<double>(), 0.0);
  EXPECT_LT(samples.at("coarse").get<double>(), 256.0 * 16);
  EXPECT_GT(samples.at("fine").get<double>(), 0.0);
  EXPECT_LE(samples.at("fine").get<double>(), 256.0 * (16 + 8));

  // A SPLATNRF header over hash-encoded settings is refused, and nothing is created.
  std::string bytes = test::read_file(dir / "out" / "model.ngp");
  bytes.replace(0, 8, "SPLATNRF");
  test::write_text(dir / "mislabelled.nerf", bytes);
  const auto bad = test::run_command(std::string(SPLAT_RENDER_EXE) + " --model " + (dir / "mislabelled.nerf").string() +
                                         " --cameras " + (tiny_dataset() / "transforms_test.json").string() +
                                         " --out " + (dir / "render_bad").string(),
                                     dir);
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("hash-encoded"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir / "render_bad"));
}

TEST(TrainCli, NgpResultDoesNotDependOnThreadCountAndResumesExactly) {
  const fs::path dir = test::scratch_dir("train_cli_ngp_threads");
  for (const char* threads : {"1", "2"}) {
    fs::create_directories(dir / threads);
    const auto r = test::run_command(
        ngp_command(dir / threads / "out", std::string("--iters 60 --test-every 0 --quiet --threads ") + threads), dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  EXPECT_TRUE(test::read_file(dir / "1" / "out" / "model.ngp") == test::read_file(dir / "2" / "out" / "model.ngp"))
      << "NGP models trained with 1 and 2 threads differ";
  auto r = test::run_command(ngp_command(dir / "split", "--iters 30 --checkpoint-every 30 --test-every 0 --quiet"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = test::run_command(ngp_command(dir / "split", "--iters 60 --test-every 0 --quiet --resume " + (dir / "split").string()),
                        dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(test::read_file(dir / "2" / "out" / "model.ngp") == test::read_file(dir / "split" / "model.ngp"))
      << "the resumed NGP model differs from the uninterrupted one";
}

TEST(TrainCli, NgpRefusesAConfigOfTheOtherMethodAndSplatOptions) {
  const fs::path dir = test::scratch_dir("train_cli_ngp_bad");
  test::write_text(dir / "nerf.json", R"({"method": "nerf"})");
  auto r = test::run_command(std::string(SPLAT_TRAIN_EXE) + " --method ngp --data " + tiny_dataset().string() +
                                 " --out " + (dir / "out").string() + " --config " + (dir / "nerf.json").string(),
                             dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("nerf.json"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("\"ngp\""), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
  r = test::run_command(ngp_command(dir / "out2", "--iters 10 --strategy official"), dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--method ngp"), std::string::npos) << r.err;
}

// The help states the defaults of the configs (their one place is the structs): it must say
// what they are.
TEST(TrainCli, HelpGivesTheConfigsDefaults) {
  const auto r = test::run_command(std::string(SPLAT_TRAIN_EXE) + " --help", test::scratch_dir("train_cli_help"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string help;  // runs of spaces and line breaks as one space
  for (char c : r.out)
    if (!(std::isspace(static_cast<unsigned char>(c)) && !help.empty() && help.back() == ' '))
      help += std::isspace(static_cast<unsigned char>(c)) ? ' ' : c;
  const SplatTrainingConfig compact = splat_training_preset("compact"), official = splat_training_preset("official");
  const NerfTrainingConfig nerf;
  const auto n = [](auto value) { return std::to_string(value); };
  for (const std::string& expected :
       {"(default " + n(compact.iterations) + " compact, " + n(official.iterations) + " official, " +
            n(nerf.iterations) + " nerf and ngp;",
        "(default " + n(compact.test_interval) + " splat, " + n(nerf.test_interval) + " nerf and ngp;",
        "(default " + n(compact.checkpoint_interval) + "; 0 = off)", "their mean (default " + n(compact.batch) + ")",
        "random seed (default " + n(compact.seed) + ")"})
    EXPECT_NE(help.find(expected), std::string::npos) << expected << " is not in the help:\n" << help;
  EXPECT_EQ(official.test_interval, compact.test_interval);
  EXPECT_EQ(official.checkpoint_interval, compact.checkpoint_interval);
  EXPECT_EQ(nerf.checkpoint_interval, compact.checkpoint_interval);
  const NerfTrainingConfig ngp = nerf_training_preset("ngp");
  EXPECT_EQ(ngp.iterations, nerf.iterations);
  EXPECT_EQ(ngp.test_interval, nerf.test_interval);
  EXPECT_EQ(ngp.checkpoint_interval, nerf.checkpoint_interval);
}

}  // namespace
}  // namespace splat

namespace splat {
namespace {

// The tiny dataset as a nerfstudio folder (one transforms.json), every photo with noise over
// its right quarter (different in every view: nothing a model can learn), and with `masks`
// a mask leaving that quarter out.
fs::path nerfstudio_folder_with_noise(const fs::path& dir, bool masks) {
  fs::create_directories(dir / "images");
  fs::create_directories(dir / "masks");
  nlohmann::json out = read_json(tiny_dataset() / "transforms_train.json");
  out["frames"] = nlohmann::json::array();
  std::uint32_t noise = 12345;
  for (const char* split : {"train", "test"}) {
    const nlohmann::json in = read_json(tiny_dataset() / ("transforms_" + std::string(split) + ".json"));
    for (nlohmann::json frame : in.at("frames")) {
      const std::string stem = fs::path(frame.at("file_path").get<std::string>()).filename().string();
      const std::string name = std::string(split) + "_" + stem + ".png";
      Image photo = read_image(tiny_dataset() / split / (stem + ".png"));
      if (photo.channels == 4) photo = composite_onto(photo, std::array<float, 3>{1, 1, 1}.data());
      Image mask(photo.width, photo.height, 1, 1.0f);
      for (int y = 0; y < photo.height; ++y)
        for (int x = 3 * photo.width / 4; x < photo.width; ++x) {
          mask.at(x, y, 0) = 0;
          for (int c = 0; c < 3; ++c) photo.at(x, y, c) = float((noise = noise * 1664525u + 1013904223u) >> 24) / 255.0f;
        }
      write_png(photo, dir / "images" / name);
      write_png(mask, dir / "masks" / name);
      frame["file_path"] = "images/" + name;
      if (masks) frame["mask_path"] = "masks/" + name;
      out["frames"].push_back(frame);
    }
  }
  test::write_text(dir / "transforms.json", out.dump(1));
  return dir;
}

// Masked pixels are neither trained on nor scored: with the masks the same photos score far
// higher, the noise left out of the PSNR; both methods train on such a folder.
TEST(TrainCli, NerfstudioMasksLeavePixelsOutOfTrainingAndScoring) {
  const fs::path dir = test::scratch_dir("train_cli_nerfstudio_masks");
  double psnr[2] = {0, 0};
  for (const bool masks : {false, true}) {
    const fs::path data = nerfstudio_folder_with_noise(dir / (masks ? "masked" : "plain"), masks);
    const fs::path out = dir / (masks ? "out_masked" : "out_plain");
    const auto r = test::run_command(std::string(SPLAT_TRAIN_EXE) + " --data " + data.string() + " --out " +
                                         out.string() + " --config " + (tiny_dataset() / "tiny_config.json").string() +
                                         " --iters 300 --holdout-every 5 --threads 2",
                                     dir);
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    const nlohmann::json m = read_json(out / "metrics.json");
    EXPECT_EQ(m.at("test").at("views").get<int>(), 3);
    psnr[masks] = m.at("test").at("psnr").get<double>();
  }
  EXPECT_GT(psnr[1], 14.0);  // measured 20.0 dB, against 11.0 without the masks
  EXPECT_GT(psnr[1], psnr[0] + 3.0) << "plain " << psnr[0] << " dB, masked " << psnr[1] << " dB";

  const fs::path nerf_out = dir / "out_nerf";
  const auto r = test::run_command(std::string(SPLAT_TRAIN_EXE) + " --method nerf --data " +
                                       (dir / "masked").string() + " --out " + nerf_out.string() +
                                       " --iters 30 --holdout-every 5",
                                   dir);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_TRUE(std::isfinite(read_json(nerf_out / "metrics.json").at("test").at("psnr").get<double>()));
}

}  // namespace
}  // namespace splat
