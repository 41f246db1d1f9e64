#include "apps/splat-eval/method_run.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>

#include "apps/splat-eval/eval_methods.hpp"
#include "apps/common/fly_through.hpp"
#include "apps/common/progress_reporter.hpp"
#include "splat/core/error.hpp"
#include "splat/data/image_io.hpp"
#include "splat/eval/pose_error.hpp"
#include "splat/train/trainer_adapter.hpp"
#include "splat/train/training_loop.hpp"

namespace splat::cli {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// The model's size as a file: written and measured, so it is exact, not an estimate.
std::uintmax_t model_file_bytes(const TrainerAdapter& trainer, const fs::path& dir) {
  const fs::path probe = dir / (".size_probe_" + trainer.model_file_name());
  trainer.write_model(probe);
  const std::uintmax_t bytes = fs::file_size(probe);
  fs::remove(probe);
  return bytes;
}

// splat-eval's side of the training loop: progress, and at each score a history entry with
// the model's exact size.
class MethodObserver final : public TrainingObserver {
 public:
  MethodObserver(const TrainerAdapter& trainer, const fs::path& dir, EvalProgress& progress)
      : trainer_(trainer), dir_(dir), progress_(progress) {}
  void on_step(const StepResult&, const LoopState& state) override {
    progress_.report("training", state.train_seconds, state.iteration);
  }
  void on_score_start(const LoopState& state) override {
    progress_.report("scoring", state.train_seconds, state.iteration, true);
  }
  void on_score(const Evaluation& e, double evaluate_seconds, const LoopState& state) override {
    const auto measure_start = Clock::now();
    history.push_back({{"seconds", state.train_seconds}, {"iteration", state.iteration},
                       {"test_psnr", e.psnr}, {"test_ssim", e.ssim},
                       {"num_gaussians", trainer_.num_gaussians()},
                       {"model_bytes", model_file_bytes(trainer_, dir_)}});
    // The ETA's time per score: the evaluation and the size probe (a whole model file).
    progress_.score_done(evaluate_seconds + seconds_since(measure_start), e.views);
    last_evaluation = e;
  }
  nlohmann::json history = nlohmann::json::array();
  Evaluation last_evaluation;

 private:
  const TrainerAdapter& trainer_;
  const fs::path& dir_;
  EvalProgress& progress_;
};

nlohmann::json pose_error_json(const PoseError& e, double scene_extent) {
  return {{"mean_rotation_deg", e.mean_rotation_deg},
          {"max_rotation_deg", e.max_rotation_deg},
          {"mean_translation_percent_of_extent", 100.0 * e.mean_translation / scene_extent},
          {"max_translation_percent_of_extent", 100.0 * e.max_translation / scene_extent},
          {"scale", e.scale}};
}

}  // namespace

MethodRun run_method(const MethodRunRequest& request, const Dataset& dataset, EvalProgress& progress) {
  const std::optional<std::string> strategy = splat_strategy(request.method);
  std::unique_ptr<TrainerAdapter> trainer =
      make_trainer(strategy ? "splat" : request.method, request.splat_config, request.nerf_config, dataset);
  fs::create_directories(request.out_dir);

  MethodRun run;
  nlohmann::json& j = run.json;
  j["method"] = request.method;
  if (strategy) j["strategy"] = request.splat_config.strategy;  // what ran: the config's
  MethodObserver observer(*trainer, request.out_dir, progress);
  TrainingLoopOptions loop;
  loop.iterations = trainer->schedule().iterations;
  loop.max_seconds = request.budget_seconds;
  loop.budget_clock = BudgetClock::kTraining;  // scoring does not eat into the budget
  loop.score_every_seconds = request.score_every.value_or(0);
  loop.score_share = kScoreShare;
  loop.score_at_end = true;  // the final scores are the last history entry's
  loop.keep_final_renders = request.render_test_views;  // the test renders are the final score's
  loop.score_views = &dataset.test;
  progress.report("training", 0, 0, true);
  const TrainingLoopResult result = run_training_loop(*trainer, loop, observer);
  const nlohmann::json& history = observer.history;
  if (result.diverged) {
    run.diverged = true;
    j["history"] = history;
    j["diverged"] = {{"iteration", result.diverged->iteration}, {"group", result.diverged->group}};
    j["train_seconds"] = result.train_seconds;
    j["iterations"] = result.diverged->iteration;
    progress.message("[" + request.method + "] " + result.diverged->message);
    return run;
  }
  const double trained_seconds = result.train_seconds;

  // The test renders are the final score's images, each view's render timed alone.
  const std::vector<double>& render_ms = observer.last_evaluation.view_render_ms;
  if (request.render_test_views) {
    run.renders = result.final_renders;
    fs::create_directories(request.out_dir / "test");
    for (std::size_t v = 0; v < run.renders.size(); ++v)
      write_png(run.renders[v], request.out_dir / "test" / (dataset.test[v].name + ".png"));
  }
  const fs::path model_file = request.out_dir / trainer->model_file_name();
  trainer->write_model(model_file);
  const std::vector<fs::path> camera_files = write_view_cameras(*trainer, dataset, request.out_dir);
  if (request.fly_through_frames > 0) {
    progress.message("[" + request.method + "] rendering the fly-through (" + std::to_string(request.fly_through_frames) +
                     " frames)");
    RenderCommandOptions fly;
    fly.model = model_file;
    fly.cameras = camera_files.front();  // the training views: the same path for every method
    fly.path = CameraPathKind::kOrbit;
    fly.frames = request.fly_through_frames;
    fly.video = request.out_dir / "orbit.mp4";
    std::copy(request.splat_config.background, request.splat_config.background + 3, fly.background);  // --bg
    fly.quiet = true;
    run_fly_through(fly);
    j["fly_through"] = fs::relative(fly.video, request.out_root).generic_string();
  }

  const double final_psnr = history.back()["test_psnr"], final_ssim = history.back()["test_ssim"];
  j["history"] = history;
  j["final"] = {{"psnr", final_psnr}, {"ssim", final_ssim}, {"views", dataset.test.size()}};
  // A model that was better earlier in the run than at its end: how much it lost (real
  // captures can learn, late, what explains the training views and spoils the rest).
  const nlohmann::json* best = &history.back();
  for (const nlohmann::json& entry : history)
    if (entry["test_psnr"].get<double>() > (*best)["test_psnr"].get<double>()) best = &entry;
  j["best"] = {{"psnr", (*best)["test_psnr"]}, {"iteration", (*best)["iteration"]}, {"seconds", (*best)["seconds"]}};
  j["drop_from_best"] = (*best)["test_psnr"].get<double>() - final_psnr;
  if (strategy) j["num_gaussians"] = trainer->num_gaussians();
  j["num_params"] = trainer->num_params();
  j["model_bytes"] = fs::file_size(model_file);
  j["model_file"] = fs::relative(model_file, request.out_root).generic_string();
  j["iterations"] = trainer->iteration();
  j["train_seconds"] = trained_seconds;
  j["eval_seconds"] = result.score_seconds;
  j["scoring"] = {{"share_limit", kScoreShare},
                  // during training, as the limit is; the final score is extra
                  {"share", (result.score_seconds - result.final_score_seconds) / std::max(1e-9, trained_seconds)},
                  {"final_score_seconds", result.final_score_seconds},
                  {"skipped_scores", result.skipped_scores}};
  j["stopped_by"] = stop_reason_name(result.stopped_by);
  if (request.render_test_views) j["render_ms_per_view_median"] = median(render_ms);
  j["config"] = trainer->config_json();
  nlohmann::json metrics;
  trainer->add_metrics(metrics);
  for (const char* key : {"pose_refinement", "exposure_compensation"})  // how the test views were scored
    if (metrics.contains(key)) j[key] = metrics[key];
  const std::vector<Camera> refined = trainer->refined_training_cameras();
  if (request.true_training_cameras && j.contains("pose_refinement") &&
      refined.size() == request.true_training_cameras->size() && refined.size() >= 3) {
    std::vector<Camera> recorded;
    for (const DatasetView& view : dataset.train) recorded.push_back(view.camera);
    j["pose_refinement"]["pose_error"] = {
        {"protocol", "training cameras against the true poses after a similarity fit of their centres"},
        {"before", pose_error_json(pose_error(recorded, *request.true_training_cameras), dataset.scene_extent)},
        {"after", pose_error_json(pose_error(refined, *request.true_training_cameras), dataset.scene_extent)}};
  }
  char line[200];
  std::snprintf(line, sizeof(line), "[%s] done: %d iterations in %s, test PSNR %.3f dB, SSIM %.4f",
                request.method.c_str(), trainer->iteration(), format_duration(trained_seconds).c_str(),
                final_psnr, final_ssim);
  progress.message(line);
  return run;
}

}  // namespace splat::cli
