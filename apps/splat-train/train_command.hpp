#pragma once
// splat-train's work: load the data, train, report progress, and write model, metrics,
// test renders and checkpoints (docs/DESIGN.md contract).
#include <filesystem>
#include <optional>

#include "splat/data/dataset.hpp"
#include "splat/train/nerf_trainer.hpp"
#include "splat/train/process_group.hpp"
#include "splat/train/resume_settings.hpp"
#include "splat/train/training_config.hpp"

namespace splat::cli {

struct TrainCommandOptions {
  std::filesystem::path data, out;
  std::optional<std::filesystem::path> resume;  // a checkpoint file, or a folder holding one
  std::string method = "splat";  // "splat" | "nerf": which config below applies
  SplatTrainingConfig config;
  NerfTrainingConfig nerf_config;
  DatasetOptions dataset;
  // The settings the command line gave (config keys → option), which --resume compares with
  // the checkpoint's (splat/train/resume_settings.hpp).
  GivenSettings given;
  int threads = 0;               // 0 = all cores
  bool quiet = false;            // no progress bar / lines
  // > 0: every this many seconds of wall time, the model so far replaces DIR/snapshot.ply
  // (or .nerf) for splat-viewer --watch; removed once the final model is written.
  double snapshot_seconds = 0;
  // The ranks of a data-parallel run (train/mpi_process_group.hpp), or null alone. Rank 0
  // reports, scores and writes every output; the others train in step with it, quietly.
  ProcessGroup* group = nullptr;
};

// Returns the process exit status: 0 done, 2 error (printed), 130 interrupted (after saving).
int run_train_command(const TrainCommandOptions& options);

}  // namespace splat::cli
