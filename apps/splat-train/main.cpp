// splat-train --data DIR --out DIR [--method splat|nerf|ngp] [--iters N] [--max-seconds S]
//             [--bg COLOUR] [--seed N] [--threads N] [--downscale K] ...
#include <cstdio>
#include <exception>
#include <memory>
#include <string>

#include "apps/common/arg_parser.hpp"
#include "apps/common/run_main.hpp"
#include "splat/train/config_file.hpp"
#include "apps/splat-train/mpi_process_group.hpp"
#include "splat/core/error.hpp"
#include "apps/splat-train/train_command.hpp"

namespace {

constexpr const char* kUsage = R"(usage: splat-train --data DIR --out DIR [options]

Trains 3D Gaussian splats on a Blender/NeRF-synthetic or COLMAP dataset on the CPU, with the
official 3DGS optimisation (L1 + SSIM loss, Adam, adaptive density control). Writes
DIR/model.ply (standard 3DGS PLY), DIR/metrics.json (history and final test metrics),
DIR/test/<view>.png, DIR/config.json, DIR/checkpoint.ckpt, and the views trained and tested
on as transforms files (DIR/cameras_train.json, DIR/cameras_test.json) that splat-render
--cameras and splat-viewer --cameras read.

  --data DIR            Blender folder (transforms_train.json, transforms_test|val.json)
                        or COLMAP folder (sparse/0, images/), detected automatically
  --out DIR             output folder (created if missing)
  --method splat|nerf|ngp
                        splat (default); nerf is the MLP NeRF baseline (writes model.nerf);
                        ngp the NeRF with Instant-NGP's hash encoding (writes model.ngp)
  --strategy compact|official
                        density control of the splats: compact (default) grows the model
                        only while it pays and prunes what contributes nothing; official
                        is the official 3DGS recipe, bit for bit
  --iters N             iterations (default 50000 compact, 30000 official, 20000 nerf
                        and ngp; with --max-seconds a NeRF trains until the time is up)
  --max-seconds S       stop after S seconds of wall time (whichever limit comes first)
  --bg COLOUR           background the RGBA images are composited onto: white, black or
                        R,G,B in [0, 1] (default white)
  --seed N              random seed (default 0); results do not depend on --threads
  --threads N           worker threads (default: all cores)
  --downscale K         train and evaluate at 1/K of the image size (default: 1, or the
                        smallest K that brings images wider than 1,600 pixels to 1,600 at
                        most, as the official trainer does; printed)
  --train-views N       train on N of the training views, spread evenly through them, the
                        test views unchanged (a sparser capture of the same scene; default all,
                        more than there are is an error)
  --holdout-every K     COLMAP data: every K-th image in name order is a test view (default
                        8; 0 = none: every view trains, and there is no test score)
  --max-gaussians N     Gaussian budget: densification never exceeds it (default: none)
  --batch B             views per optimiser step, the loss their mean (default 1); iterations
                        still count views, so --iters must be a multiple of B
  --refine-poses        optimise a correction of every training view's pose with the scene
                        (for poses with some error, as estimated ones have); the test views
                        are then aligned to their photographs with the model fixed before
                        they are scored (off by default: the model then fits its own
                        poses, not the recorded ones; metrics.json's pose_refinement
                        scores both)
  --exposure-compensation
                        give every training view its own affine colour map (exposure and
                        white balance), optimised with the scene; test views use none
                        (experimental: off by default)
  --test-every N        evaluate the test views every N iterations (default 1000 splat,
                        2000 nerf and ngp; 0 = end only)
  --checkpoint-every N  write DIR/checkpoint.ckpt every N iterations (default 5000; 0 = off)
  --resume PATH         continue from a checkpoint file or a folder holding checkpoint.ckpt
  --snapshot-every S    every S seconds, write the model so far to DIR/snapshot.ply (.nerf, .ngp)
                        for splat-viewer --watch DIR (removed when the final model is written)
  --config FILE         JSON with any settings of config.json (applied before the options)
  --quiet               no progress output
Ctrl-C saves a checkpoint and a valid model.ply, then exits with status 130.
On a real capture (COLMAP data with its points) the compact strategy holds one training
view in 32 out (the most redundant) for the first half of growth; if by then they score
more than 0.3 dB below their best, training stops on the best model (stopped_by "validation"),
otherwise they rejoin training (settings validation_*, metrics.json "validation").
)";

// The options both methods share, over the defaults and the --config file. Both config
// structs name these fields alike.
template <class Config>
void apply_options(const splat::cli::ArgParser& args, Config& config,
                   splat::cli::TrainCommandOptions& options) {
  if (auto file = args.value("config")) {
    const nlohmann::json settings = splat::read_config_json(*file);
    splat::apply_config_json(*file, settings, config);
    for (const auto& [key, value] : settings.items()) options.given[key] = "--config " + *file;
  }
  // Each option that sets a config key records it (given), for --resume to compare.
  const auto given = [&](const char* option, const char* key) { options.given[key] = std::string("--") + option; };
  if (auto n = args.integer("iters", splat::setting_ranges::kPositiveIterations)) {
    config.iterations = *n;
    given("iters", "iterations");
  }
  if (auto s = args.number("max-seconds", {0.01, splat::kMaxTrainingSeconds})) {
    config.max_seconds = *s;
    given("max-seconds", "max_seconds");
  }
  const std::array<float, 3> bg = args.colour("bg").value_or(std::array<float, 3>{1, 1, 1});
  for (int c = 0; c < 3; ++c) config.background[c] = options.dataset.background[c] = bg[c];
  if (args.value("bg"))  // the splats' config names each channel, the NeRF's the triple
    for (const char* key : {"background", "background_r", "background_g", "background_b"}) given("bg", key);
  if (auto seed = args.integer("seed", {0, 2147483647})) {
    config.seed = unsigned(*seed);
    given("seed", "seed");
  }
  if (auto n = args.integer("test-every", splat::setting_ranges::kIterations)) {
    config.test_interval = *n;
    given("test-every", "test_interval");
  }
  if (auto n = args.integer("checkpoint-every", splat::setting_ranges::kIterations)) {
    config.checkpoint_interval = *n;
    given("checkpoint-every", "checkpoint_interval");
  }
}

// splat-train's work in this process (alone, or one rank of a data-parallel run).
int train_main(int argc, char** argv, splat::ProcessGroup* ranks) {
  splat::cli::ArgParser args(argc, argv,
                             {"data", "out", "method", "strategy", "iters", "max-seconds", "bg", "seed",
                              "threads", "downscale", "train-views", "holdout-every", "max-gaussians", "batch",
                              "test-every", "checkpoint-every", "resume", "config", "snapshot-every"},
                             {"help", "quiet", "refine-poses", "exposure-compensation"});
  if (args.has("help")) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  args.expect_no_positionals();
  splat::cli::TrainCommandOptions options;
  options.data = args.required("data");
  options.out = args.required("out");
  options.method = args.value("method").value_or("splat");
  if (options.method != "splat" && options.method != "nerf" && options.method != "ngp")
    throw splat::ArgumentError("--method must be splat, nerf or ngp, got '" + options.method + "'");
  const std::string method_option = "--method " + options.method;
  if (options.method != "splat") {
    if (args.value("max-gaussians"))
      throw splat::ArgumentError("--max-gaussians is a splat setting; " + method_option + " has no Gaussians");
    if (args.value("strategy"))
      throw splat::ArgumentError("--strategy is a splat setting; " + method_option + " has no density control");
    if (args.has("refine-poses"))
      throw splat::ArgumentError("--refine-poses is a splat setting; the NeRF does not refine poses");
    if (args.has("exposure-compensation"))
      throw splat::ArgumentError("--exposure-compensation is a splat setting; the NeRF has no exposure maps");
    if (args.value("batch"))
      throw splat::ArgumentError("--batch is a splat setting; the NeRF's steps are batches of rays (rays_per_batch)");
    options.nerf_config = splat::nerf_training_preset(options.method);
    apply_options(args, options.nerf_config, options);
    // A time budget is the NeRF's limit (its rate decays over it): its default iteration
    // count, a limit for runs without one, does not cut it short.
    if (args.value("max-seconds") && !args.value("iters") &&
        options.nerf_config.iterations == splat::nerf_training_preset(options.method).iterations)
      options.nerf_config.iterations = splat::kNerfIterationsUnderBudget;
  } else {
    const auto strategy = args.value("strategy");
    options.config = splat::splat_training_preset(strategy.value_or("compact"));
    apply_options(args, options.config, options);
    if (strategy && options.config.strategy != *strategy)
      throw splat::ArgumentError("--strategy " + *strategy + " conflicts with the config file's strategy '" +
                                 options.config.strategy + "'");
    if (strategy) options.given["strategy"] = "--strategy";
    if (auto n = args.integer("max-gaussians", {1, splat::kMaxGaussiansSetting})) {
      options.config.density.max_gaussians = std::size_t(*n);
      options.given["max_gaussians"] = "--max-gaussians";
    }
    if (auto n = args.integer("batch", {1, splat::kMaxBatchViews})) {
      options.config.batch = *n;
      options.given["batch"] = "--batch";
    }
    if (args.has("refine-poses")) {
      options.config.refine_poses = true;
      options.given["refine_poses"] = "--refine-poses";
    }
    if (args.has("exposure-compensation")) {
      options.config.exposure_compensation = true;
      options.given["exposure_compensation"] = "--exposure-compensation";
    }
  }
  if (auto n = args.integer("threads", splat::cli::kThreadsRange)) options.threads = *n;
  if (auto k = args.integer("downscale", splat::kDownscaleRange)) options.dataset.downscale = *k;
  else options.dataset.max_width = splat::kDefaultMaxImageWidth;
  if (auto n = args.integer("train-views", {1, splat::kMaxViews})) options.dataset.train_views = *n;
  if (auto k = args.integer("holdout-every", {0, splat::kMaxViews})) options.dataset.holdout_every = *k;
  if (auto r = args.value("resume")) options.resume = *r;
  options.quiet = args.has("quiet") || (ranks && ranks->rank() != 0);  // rank 0 reports
  if (auto s = args.number("snapshot-every", {0.1, splat::kMaxTrainingSeconds})) options.snapshot_seconds = *s;
  // Settings that must agree with each other are checked once all are in: a conflict that
  // involves the config file names it.
  try {
    if (options.method != "splat") splat::validate(options.nerf_config);
    else splat::validate(options.config);
  } catch (const splat::ArgumentError& e) {
    if (auto file = args.value("config")) throw splat::InputError(*file, std::string(e.what()) + " (with the options)");
    throw;
  }
  options.group = ranks;
  return splat::cli::run_train_command(options);
}

}  // namespace

int main(int argc, char** argv) {
  // Under an MPI launcher, the ranks of a data-parallel run (mpi_process_group.hpp).
  std::unique_ptr<splat::ProcessGroup> ranks;
  const int status = splat::cli::run_main([&] {
    ranks = splat::cli::join_launched_ranks(argc, argv);
    if (ranks && ranks->size() > 1) {
      try {
        return train_main(argc, argv, ranks.get());
      } catch (const std::exception& e) {  // name the rank that failed
        throw splat::Error("rank " + std::to_string(ranks->rank()) + " of " + std::to_string(ranks->size()) +
                           ": " + e.what());
      }
    }
    return train_main(argc, argv, ranks.get());
  });
  // A rank that failed alone would leave the others waiting in the next exchange: end them
  // all (a run that stopped everywhere at once, by an interrupt, returns normally).
  if (ranks && ranks->size() > 1 && status != 0 && status != 130) splat::cli::abort_all_ranks(status);
  return status;
}
