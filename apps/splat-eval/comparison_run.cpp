#include <tbb/info.h>

#include "apps/splat-eval/eval_methods.hpp"
#include "apps/splat-eval/eval_modes.hpp"
#include "apps/splat-eval/method_run.hpp"
#include "apps/common/progress_reporter.hpp"
#include "splat/core/error.hpp"
#include "splat/data/image_io.hpp"
#include "splat/eval/comparison_grid.hpp"

namespace splat::cli {

void run_comparison(const EvalCommandOptions& options, const Dataset& dataset) {
  namespace fs = std::filesystem;
  const std::vector<std::string> methods = methods_to_run(options);
  const double score_every = options.eval_every.value_or(options.max_seconds / 10);
  EvalProgress progress(options.quiet, int(methods.size()), options.max_seconds, kScoreShare,
                        int(dataset.test.size()));
  progress.message("comparison on " + options.data.string() + " (" + std::to_string(dataset.train.size()) +
                   " train, " + std::to_string(dataset.test.size()) + " test views), budget " +
                   format_duration(options.max_seconds) + " per method");
  std::vector<MethodRun> runs;
  for (std::size_t i = 0; i < methods.size(); ++i) {
    const std::string& method = methods[i];
    progress.start_run(int(i), method);
    MethodRunRequest request = method_request(options, method, options.out / method);
    request.score_every = score_every;
    request.render_test_views = true;
    request.fly_through_frames = options.fly_through_frames;
    runs.push_back(run_method(request, dataset, progress));
    if (runs.back().diverged)
      throw Error(method + " training diverged at iteration " + runs.back().json["diverged"]["iteration"].dump() +
                  " (non-finite " + runs.back().json["diverged"]["group"].get<std::string>() +
                  "); splat-eval --stability records divergence instead of stopping");
  }

  progress.message("writing comparison grids");
  fs::create_directories(options.out / "grids");
  for (std::size_t v = 0; v < dataset.test.size(); ++v) {
    std::vector<const Image*> renders;
    for (const MethodRun& run : runs) renders.push_back(&run.renders[v]);
    write_png(comparison_grid(dataset.test[v].image, renders), options.out / "grids" / (dataset.test[v].name + ".png"));
  }

  nlohmann::json j;
  j["data"] = options.data.string();
  j["budget_seconds"] = options.max_seconds;
  j["eval_every_seconds"] = score_every;
  j["threads"] = options.threads > 0 ? options.threads : tbb::info::default_concurrency();
  j["test_views"] = dataset.test.size();
  j["width"] = dataset.test.front().image.width;
  j["height"] = dataset.test.front().image.height;
  nlohmann::json panels = {"ground truth"};
  for (const std::string& method : methods) panels.push_back(method);
  for (const std::string& method : methods) panels.push_back(method + " error");
  j["grid"] = {{"panels", panels},
               {"error_map", "grey = min(1, " + std::to_string(int(kErrorMapGain)) +
                                 " * mean over RGB of |render - truth|)"}};
  j["grids"] = nlohmann::json::array();
  for (const DatasetView& view : dataset.test) j["grids"].push_back("grids/" + view.name + ".png");
  j["methods"] = nlohmann::json::array();
  for (const MethodRun& run : runs) j["methods"].push_back(run.json);
  write_json_file(options.out / "results.json", j);
}

}  // namespace splat::cli
