#pragma once
// splat-eval's work: train the splat model and the NeRF on one dataset with the same
// wall-clock budget and threads, score the test views at regular points of training time,
// render the test views with both final models (timed), and write results.json, the models,
// the renders and side-by-side comparison grids (DESIGN.md contract).
#include <filesystem>
#include <optional>

#include "splat/data/dataset.hpp"
#include "splat/train/nerf_trainer.hpp"
#include "splat/train/training_config.hpp"

namespace splat::cli {

struct EvalCommandOptions {
  std::filesystem::path data, out;
  double max_seconds = 600;          // training budget per method, wall clock
  std::optional<double> eval_every;  // seconds of training time between test scores; default max/10
  int threads = 0;                   // 0 = all cores
  SplatTrainingConfig splat_config;
  NerfTrainingConfig nerf_config;
  DatasetOptions dataset;
  bool quiet = false;
};

// Returns the process exit status: 0 done (errors are thrown, run_main prints them).
int run_eval_command(const EvalCommandOptions& options);

}  // namespace splat::cli
