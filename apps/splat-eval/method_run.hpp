#pragma once
// One training run inside splat-eval: a method trained on a dataset for a budget of training
// time (wall time minus scoring time), scored on the test views every
// `score_every` seconds of training and at the end, its model written and measured.
// Comparison, stability and sweep runs are all made of these.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "apps/splat-eval/eval_progress.hpp"
#include "apps/splat-eval/result_files.hpp"
#include "splat/core/image.hpp"
#include "splat/data/dataset.hpp"
#include "splat/train/nerf_trainer.hpp"
#include "splat/train/training_config.hpp"

namespace splat::cli {

// The share of a run's training time that its scores during training may take (the final
// score is extra): splat-eval's curves are scored no more often than that allows.
constexpr double kScoreShare = 0.1;

struct MethodRunRequest {
  std::string method;  // "splat" | "splat-official" | "nerf" | "ngp" (eval_methods.hpp)
  SplatTrainingConfig splat_config;
  NerfTrainingConfig nerf_config;
  double budget_seconds = 600;
  std::optional<double> score_every;  // none: score once, at the end
  std::filesystem::path out_root;     // splat-eval's --out: file names in the JSON are relative to it
  std::filesystem::path out_dir;      // receives the model (and test/<view>.png with renders)
  bool render_test_views = false;     // keep and write the final score's renders (each timed alone)
  // The training poses before a stability condition perturbed them: under pose refinement,
  // how far the training cameras are from these, before and after training, is measured.
  const std::vector<Camera>* true_training_cameras = nullptr;
  // > 0: an orbit of this many frames round the training views' centre, out_dir/orbit.mp4,
  // framed from the cameras so that every method flies the same path.
  int fly_through_frames = 0;
};

struct MethodRun {
  // method, strategy (splat methods), history [{seconds, iteration, test_psnr, test_ssim,
  // num_gaussians, model_bytes}], final {psnr, ssim, views}, best {psnr, iteration, seconds}
  // (the best test point), drop_from_best (its PSNR minus the final), num_gaussians (splat methods),
  // num_params, model_bytes, model_file
  // (relative to out_root), iterations, train_seconds, eval_seconds, stopped_by,
  // render_ms_per_view_median (with renders), fly_through (the orbit video, relative to
  // out_root, when asked for), config; or, when training diverged,
  // diverged {iteration, group} and no final scores or model.
  nlohmann::json json;
  std::vector<Image> renders;  // [test view], with render_test_views
  bool diverged = false;
};

MethodRun run_method(const MethodRunRequest& request, const Dataset& dataset, EvalProgress& progress);

}  // namespace splat::cli
