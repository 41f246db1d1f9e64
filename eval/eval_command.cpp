#include "eval_command.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include "charts.hpp"
#include "progress_reporter.hpp"
#include "splat/core/atomic_file.hpp"
#include "splat/core/error.hpp"
#include "splat/data/image_io.hpp"
#include "splat/eval/comparison_grid.hpp"
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

// What one method's run produced; the renders feed the comparison grids.
struct MethodResult {
  nlohmann::json json;
  std::vector<Image> renders;  // [test view]
};

// Progress for the whole run: the stage and an ETA over both methods. Training time is
// known in advance (the budget); evaluation time is estimated from the scores done so far.
class EvalProgress {
 public:
  EvalProgress(bool quiet, double budget, int evaluations_per_method)
      : quiet_(quiet), budget_(budget), evaluations_per_method_(evaluations_per_method) {}

  void set_method(int index, const std::string& name) {
    method_index_ = index;
    method_ = name;
  }
  void evaluation_done(double seconds) {
    eval_seconds_ += seconds;
    ++evaluations_;
  }
  // Prints at most every kInterval seconds unless `force`.
  void report(const std::string& stage, double train_seconds, int iteration, bool force = false) {
    if (quiet_) return;
    if (!force && printed_ && seconds_since(last_) < kInterval) return;
    printed_ = true;
    last_ = Clock::now();
    const double training_left = budget_ * (kMethods - method_index_) - std::min(train_seconds, budget_);
    const double per_eval = evaluations_ > 0 ? eval_seconds_ / evaluations_ : 0;
    const int evals_left = std::max(0, evaluations_per_method_ * kMethods - evaluations_);
    const double eta = std::max(0.0, training_left) + per_eval * evals_left;
    std::printf("[%s %d/%d] %s: %.1f of %.1f s trained, iteration %d, ETA %s\n", method_.c_str(),
                method_index_ + 1, kMethods, stage.c_str(), train_seconds, budget_, iteration,
                format_duration(eta).c_str());
    std::fflush(stdout);
  }
  void message(const std::string& text) {
    if (quiet_) return;
    std::printf("%s\n", text.c_str());
    std::fflush(stdout);
  }

 private:
  static constexpr int kMethods = 2;
  static constexpr double kInterval = 5.0;
  bool quiet_;
  double budget_;
  int evaluations_per_method_;
  int method_index_ = 0, evaluations_ = 0;
  double eval_seconds_ = 0;
  std::string method_;
  bool printed_ = false;
  Clock::time_point last_;
};

void write_json(const fs::path& file, const nlohmann::json& json) {
  write_atomically(file, [&](const fs::path& temp) {
    std::ofstream out(temp);
    out << json.dump(1) << "\n";
    if (!out) throw InputError(file, "cannot write the file");
  });
}

// Trains one method for the budget (training time: wall time minus the time spent scoring),
// scoring the test views every `eval_every` seconds of training time and at the end; then
// renders each test view alone, timed, and writes the model and the renders under out/method.
MethodResult run_method(const EvalCommandOptions& options, const std::string& method, const Dataset& dataset,
                        EvalProgress& progress) {
  TrainCommandOptions train_options;
  train_options.method = method;
  train_options.config = options.splat_config;
  train_options.nerf_config = options.nerf_config;
  std::unique_ptr<TrainerAdapter> trainer = make_trainer(train_options, dataset);
  const int max_iterations = trainer->schedule().iterations;
  const double budget = options.max_seconds;
  const double eval_every = options.eval_every.value_or(budget / 10);

  nlohmann::json history = nlohmann::json::array();
  double eval_seconds = 0;
  const auto start = Clock::now();
  auto train_seconds = [&] { return seconds_since(start) - eval_seconds; };
  auto score = [&] {
    progress.report("evaluating", train_seconds(), trainer->iteration(), true);
    const auto eval_start = Clock::now();
    const double seconds = train_seconds();
    const Evaluation e = trainer->evaluate(dataset.test, nullptr);
    // The model's size now (the splat model grows as it densifies): written and measured,
    // so it is the exact file size, not an estimate.
    const fs::path sized = options.out / (".size_probe_" + trainer->model_file_name());
    trainer->write_model(sized);
    const std::uintmax_t bytes = fs::file_size(sized);
    fs::remove(sized);
    history.push_back({{"seconds", seconds}, {"iteration", trainer->iteration()},
                       {"test_psnr", e.psnr}, {"test_ssim", e.ssim},
                       {"num_gaussians", trainer->num_gaussians()}, {"model_bytes", bytes}});
    const double spent = seconds_since(eval_start);
    eval_seconds += spent;
    progress.evaluation_done(spent);
  };

  double next_eval = eval_every;
  progress.report("training", 0, 0, true);
  while (trainer->iteration() < max_iterations && train_seconds() < budget) {
    if (train_seconds() >= next_eval) {
      score();
      while (next_eval <= train_seconds()) next_eval += eval_every;
    }
    trainer->step();
    progress.report("training", train_seconds(), trainer->iteration());
  }
  const double trained_seconds = train_seconds();
  trainer->check_parameters_finite();
  if (history.empty() || history.back()["iteration"] != trainer->iteration()) score();

  // Final renders, one view at a time so each is timed alone (the render only, not the
  // scoring). The final scores are the last history entry's: the same model, same images.
  progress.report("rendering", trained_seconds, trainer->iteration(), true);
  MethodResult result;
  std::vector<double> render_ms;
  for (const DatasetView& view : dataset.test) {
    const auto render_start = Clock::now();
    result.renders.push_back(trainer->render(view.camera));
    render_ms.push_back(1000.0 * seconds_since(render_start));
  }
  const double final_psnr = history.back()["test_psnr"], final_ssim = history.back()["test_ssim"];

  const fs::path dir = options.out / method;
  fs::create_directories(dir / "test");
  for (std::size_t i = 0; i < result.renders.size(); ++i)
    write_png(result.renders[i], dir / "test" / (dataset.test[i].name + ".png"));
  const fs::path model_file = dir / trainer->model_file_name();
  trainer->write_model(model_file);

  nlohmann::json& j = result.json;
  j["method"] = method;
  j["history"] = history;
  j["final"] = {{"psnr", final_psnr}, {"ssim", final_ssim}, {"views", dataset.test.size()}};
  if (method == "splat") j["num_gaussians"] = trainer->num_gaussians();
  j["num_params"] = trainer->num_params();
  j["model_bytes"] = fs::file_size(model_file);
  j["model_file"] = fs::relative(model_file, options.out).generic_string();
  j["iterations"] = trainer->iteration();
  j["train_seconds"] = trained_seconds;
  j["eval_seconds"] = eval_seconds;
  j["stopped_by"] = trainer->iteration() >= max_iterations ? "iterations" : "time";
  j["render_ms_per_view_median"] = median(render_ms);
  j["config"] = trainer->config_json();
  char line[200];
  std::snprintf(line, sizeof(line), "[%s] done: %d iterations in %s, test PSNR %.3f dB, SSIM %.4f, %.1f ms/view",
                method.c_str(), trainer->iteration(), format_duration(trained_seconds).c_str(),
                final_psnr, final_ssim, median(render_ms));
  progress.message(line);
  return result;
}

}  // namespace

int run_eval_command(const EvalCommandOptions& options) {
  if (options.max_seconds <= 0) throw ArgumentError("--max-seconds must be > 0");
  if (options.eval_every && *options.eval_every <= 0) throw ArgumentError("--eval-every-seconds must be > 0");
  std::unique_ptr<tbb::global_control> threads;
  if (options.threads > 0)
    threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                    std::size_t(options.threads));
  // Load before touching --out, so bad input leaves nothing behind.
  const Dataset dataset = load_dataset(options.data, options.dataset);
  if (dataset.train.empty()) throw InputError(options.data, "the dataset has no training views");
  if (dataset.test.empty()) throw InputError(options.data, "the dataset has no test views");
  std::error_code ec;
  fs::create_directories(options.out, ec);
  if (!fs::is_directory(options.out)) throw InputError(options.out, "cannot create the output folder");

  const double eval_every = options.eval_every.value_or(options.max_seconds / 10);
  EvalProgress progress(options.quiet, options.max_seconds, int(options.max_seconds / eval_every) + 1);
  progress.message("data: " + options.data.string() + " (" + std::to_string(dataset.train.size()) +
                   " train, " + std::to_string(dataset.test.size()) + " test views), budget " +
                   format_duration(options.max_seconds) + " per method");
  std::vector<MethodResult> results;
  const char* methods[] = {"splat", "nerf"};
  for (int i = 0; i < 2; ++i) {
    progress.set_method(i, methods[i]);
    results.push_back(run_method(options, methods[i], dataset, progress));
  }

  progress.message("writing comparison grids");
  fs::create_directories(options.out / "grids");
  for (std::size_t v = 0; v < dataset.test.size(); ++v)
    write_png(comparison_grid(dataset.test[v].image, results[0].renders[v], results[1].renders[v]),
              options.out / "grids" / (dataset.test[v].name + ".png"));

  nlohmann::json j;
  j["data"] = options.data.string();
  j["budget_seconds"] = options.max_seconds;
  j["eval_every_seconds"] = eval_every;
  j["threads"] = options.threads > 0 ? options.threads : tbb::info::default_concurrency();
  j["test_views"] = dataset.test.size();
  j["width"] = dataset.test.front().image.width;
  j["height"] = dataset.test.front().image.height;
  j["grid"] = {{"panels", {"ground truth", "splat", "nerf", "splat error", "nerf error"}},
               {"error_map", "grey = min(1, " + std::to_string(int(kErrorMapGain)) +
                                 " * mean over RGB of |render - truth|)"}};
  j["methods"] = nlohmann::json::array();
  for (const MethodResult& r : results) j["methods"].push_back(r.json);
  progress.message("drawing charts");
  const std::vector<std::string> charts = write_charts(j["methods"], options.out / "charts");
  if (charts.empty()) std::fprintf(stderr, "warning: gnuplot not found, no charts drawn (install gnuplot-nox)\n");
  j["charts"] = nlohmann::json::array();
  for (const std::string& chart : charts) j["charts"].push_back("charts/" + chart);
  // Last, so a results.json present means the run finished.
  write_json(options.out / "results.json", j);
  progress.message("outputs: " + (options.out / "results.json").string() + ", splat/, nerf/, grids/, charts/");
  return 0;
}

}  // namespace splat::cli
