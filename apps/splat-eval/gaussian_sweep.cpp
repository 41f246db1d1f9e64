#include <algorithm>
#include <tbb/info.h>

#include "apps/splat-eval/eval_methods.hpp"
#include "apps/splat-eval/eval_modes.hpp"
#include "apps/splat-eval/method_run.hpp"
#include "apps/common/progress_reporter.hpp"

namespace splat::cli {

void run_gaussian_sweep(const EvalCommandOptions& options, const Dataset& dataset) {
  const std::vector<std::size_t>& budgets = options.sweep_gaussians;
  const std::string method = methods_to_run(options).front();  // one splat method
  EvalProgress progress(options.quiet, int(budgets.size()), options.max_seconds, 0, int(dataset.test.size()));
  progress.message("Gaussian budget sweep on " + options.data.string() + ": " + std::to_string(budgets.size()) +
                   " " + method + " runs of " + format_duration(options.max_seconds));
  nlohmann::json runs = nlohmann::json::array();
  for (std::size_t i = 0; i < budgets.size(); ++i) {
    const std::string label = "max " + std::to_string(budgets[i]) + " Gaussians";
    progress.start_run(int(i), label);
    MethodRunRequest request = method_request(options, method, options.out / "sweep" / std::to_string(budgets[i]));
    request.splat_config.density.max_gaussians = budgets[i];
    request.render_test_views = true;  // for the render time; the images are kept too
    MethodRun run = run_method(request, dataset, progress);
    run.json.erase("config");
    run.json["max_gaussians"] = budgets[i];
    runs.push_back(run.json);
  }

  // The smallest model (in bytes) within 0.5 dB of the best PSNR the sweep reached.
  constexpr double kWithinDb = 0.5;
  double best = -1;
  for (const auto& r : runs)
    if (r.contains("final")) best = std::max(best, r["final"]["psnr"].get<double>());
  std::optional<std::size_t> smallest;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (!runs[i].contains("final") || runs[i]["final"]["psnr"].get<double>() < best - kWithinDb) continue;
    if (!smallest || runs[i]["model_bytes"] < runs[*smallest]["model_bytes"]) smallest = i;
  }

  nlohmann::json j;
  j["data"] = options.data.string();
  j["method"] = method;
  j["strategy"] = *splat_strategy(method);
  j["budget_seconds"] = options.max_seconds;
  j["threads"] = options.threads > 0 ? options.threads : tbb::info::default_concurrency();
  j["runs"] = runs;
  j["best_psnr"] = best;
  j["within_db"] = kWithinDb;
  if (smallest) j["smallest_within"] = *smallest;  // index into runs
  write_json_file(options.out / "sweep.json", j);
}

}  // namespace splat::cli
