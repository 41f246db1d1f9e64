#pragma once
// splat-eval's work on one dataset, as one of three runs (eval_modes.hpp): the comparison of
// the methods (eval_methods.hpp) under the same training-time budget and threads (docs/DESIGN.md
// contract), the stability conditions, or a sweep of Gaussian budgets. Each ends by redrawing
// the charts and report.html from every result file in --out.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "splat/data/dataset.hpp"
#include "splat/train/nerf_trainer.hpp"

namespace splat::cli {

struct PoseNoiseLevel {
  double rotation_deg, translation_fraction;  // of the scene extent
};

// The kinds of stability condition, as --stability-conditions names them: all training views;
// the same with pose refinement (splat methods only); fewer views; pose noise; pose noise with
// refinement (splat methods only); random initialisation.
inline const char* const kStabilityKinds[] = {"baseline", "views", "pose-noise", "refinement", "random-init"};

enum class EvalMode { kComparison, kStability, kGaussianSweep };

struct EvalCommandOptions {
  EvalMode mode = EvalMode::kComparison;
  std::filesystem::path data, out;
  std::vector<std::string> methods;  // --methods, in run order; empty: the mode's default
  double max_seconds = 600;          // training budget per run (scoring not counted)
  std::optional<double> eval_every;  // seconds of training time between test scores; default max/10
  int threads = 0;                   // 0 = all cores
  // --splat-config's settings (no "strategy"), applied over each splat method's preset.
  nlohmann::json splat_settings = nlohmann::json::object();
  NerfTrainingConfig nerf_config = nerf_training_preset("nerf");
  NerfTrainingConfig ngp_config = nerf_training_preset("ngp");
  DatasetOptions dataset;
  bool quiet = false;
  // Stability conditions: which kinds run (kStabilityKinds), training views kept, and pose
  // noise levels.
  std::vector<std::string> stability_kinds;  // empty: all
  std::vector<int> stability_views = {8, 16, 32};
  std::vector<PoseNoiseLevel> pose_noise_levels = {{0.25, 0.0025}, {1.0, 0.01}, {3.0, 0.03}};
  std::vector<std::size_t> sweep_gaussians;  // the sweep's Gaussian budgets
  int fly_through_frames = 0;                // > 0: each compared method's orbit.mp4 of that many frames
};

// Returns the process exit status: 0 done (errors are thrown, run_main prints them).
int run_eval_command(const EvalCommandOptions& options);

// Redraws out/charts and out/report.html from the result files already in `out`; returns 0.
int redraw_report(const std::filesystem::path& out, bool quiet);

}  // namespace splat::cli
