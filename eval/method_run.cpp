#include "method_run.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>

#include "progress_reporter.hpp"
#include "splat/core/error.hpp"
#include "splat/data/image_io.hpp"
#include "trainer_adapter.hpp"

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

}  // namespace

MethodRun run_method(const MethodRunRequest& request, const Dataset& dataset, EvalProgress& progress) {
  TrainCommandOptions train_options;
  train_options.method = request.method;
  train_options.config = request.splat_config;
  train_options.nerf_config = request.nerf_config;
  std::unique_ptr<TrainerAdapter> trainer = make_trainer(train_options, dataset);
  const int max_iterations = trainer->schedule().iterations;
  const double budget = request.budget_seconds;
  fs::create_directories(request.out_dir);

  MethodRun run;
  nlohmann::json& j = run.json;
  j["method"] = request.method;
  nlohmann::json history = nlohmann::json::array();
  double eval_seconds = 0;
  const auto start = Clock::now();
  auto train_seconds = [&] { return seconds_since(start) - eval_seconds; };
  auto score = [&] {
    progress.report("scoring", train_seconds(), trainer->iteration(), true);
    const auto eval_start = Clock::now();
    const double seconds = train_seconds();
    const Evaluation e = trainer->evaluate(dataset.test, nullptr);
    history.push_back({{"seconds", seconds}, {"iteration", trainer->iteration()},
                       {"test_psnr", e.psnr}, {"test_ssim", e.ssim},
                       {"num_gaussians", trainer->num_gaussians()},
                       {"model_bytes", model_file_bytes(*trainer, request.out_dir)}});
    const double spent = seconds_since(eval_start);
    eval_seconds += spent;
    progress.score_done(spent);
  };

  double next_score = request.score_every.value_or(budget + 1);
  progress.report("training", 0, 0, true);
  try {
    while (trainer->iteration() < max_iterations && train_seconds() < budget) {
      if (request.score_every && train_seconds() >= next_score) {
        score();
        while (next_score <= train_seconds()) next_score += *request.score_every;
      }
      trainer->step();
      progress.report("training", train_seconds(), trainer->iteration());
    }
    trainer->check_parameters_finite();
  } catch (const TrainingDiverged& diverged) {
    run.diverged = true;
    j["history"] = history;
    j["diverged"] = {{"iteration", diverged.iteration()}, {"group", diverged.group()}};
    j["train_seconds"] = train_seconds();
    j["iterations"] = diverged.iteration();
    progress.message("[" + request.method + "] " + diverged.what());
    return run;
  }
  const double trained_seconds = train_seconds();
  if (history.empty() || history.back()["iteration"] != trainer->iteration()) score();

  // One view at a time so each is timed alone: the render only, not the scoring. The final
  // scores are the last history entry's: the same model, the same images.
  std::vector<double> render_ms;
  if (request.render_test_views) {
    progress.report("rendering", trained_seconds, trainer->iteration(), true);
    fs::create_directories(request.out_dir / "test");
    for (const DatasetView& view : dataset.test) {
      const auto render_start = Clock::now();
      run.renders.push_back(trainer->render(view.camera));
      render_ms.push_back(1000.0 * seconds_since(render_start));
      write_png(run.renders.back(), request.out_dir / "test" / (view.name + ".png"));
    }
  }
  const fs::path model_file = request.out_dir / trainer->model_file_name();
  trainer->write_model(model_file);

  const double final_psnr = history.back()["test_psnr"], final_ssim = history.back()["test_ssim"];
  j["history"] = history;
  j["final"] = {{"psnr", final_psnr}, {"ssim", final_ssim}, {"views", dataset.test.size()}};
  if (request.method == "splat") j["num_gaussians"] = trainer->num_gaussians();
  j["num_params"] = trainer->num_params();
  j["model_bytes"] = fs::file_size(model_file);
  j["model_file"] = fs::relative(model_file, request.out_root).generic_string();
  j["iterations"] = trainer->iteration();
  j["train_seconds"] = trained_seconds;
  j["eval_seconds"] = eval_seconds;
  j["stopped_by"] = trainer->iteration() >= max_iterations ? "iterations" : "time";
  if (request.render_test_views) j["render_ms_per_view_median"] = median(render_ms);
  j["config"] = trainer->config_json();
  char line[200];
  std::snprintf(line, sizeof(line), "[%s] done: %d iterations in %s, test PSNR %.3f dB, SSIM %.4f",
                request.method.c_str(), trainer->iteration(), format_duration(trained_seconds).c_str(),
                final_psnr, final_ssim);
  progress.message(line);
  return run;
}

}  // namespace splat::cli
