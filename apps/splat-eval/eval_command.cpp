#include "apps/splat-eval/eval_command.hpp"

#include <cstdio>

#include "apps/splat-eval/charts.hpp"
#include "apps/common/thread_limit.hpp"
#include "apps/splat-eval/eval_methods.hpp"
#include "apps/splat-eval/eval_modes.hpp"
#include "apps/splat-eval/report.hpp"
#include "splat/core/error.hpp"

namespace splat::cli {

int run_eval_command(const EvalCommandOptions& options) {
  namespace fs = std::filesystem;
  if (options.max_seconds <= 0) throw ArgumentError("--max-seconds must be > 0");
  if (options.eval_every && *options.eval_every <= 0) throw ArgumentError("--eval-every-seconds must be > 0");
  if (options.mode == EvalMode::kGaussianSweep && options.sweep_gaussians.empty())
    throw ArgumentError("--sweep-gaussians needs at least one budget");
  methods_to_run(options);  // ArgumentError for a list the mode cannot run
  const auto thread_limit = limit_threads(options.threads);
  // Load before touching --out, so bad input leaves nothing behind.
  const Dataset dataset = load_dataset(options.data, options.dataset);
  if (dataset.train.empty()) throw InputError(options.data, "the dataset has no training views");
  if (dataset.test.empty()) throw InputError(options.data, "the dataset has no test views");
  std::error_code ec;
  fs::create_directories(options.out, ec);
  if (!fs::is_directory(options.out)) throw InputError(options.out, "cannot create the output folder");

  switch (options.mode) {
    case EvalMode::kComparison: run_comparison(options, dataset); break;
    case EvalMode::kStability: run_stability(options, dataset); break;
    case EvalMode::kGaussianSweep: run_gaussian_sweep(options, dataset); break;
  }

  return redraw_report(options.out, options.quiet);
}

int redraw_report(const std::filesystem::path& out, bool quiet) {
  if (!std::filesystem::is_directory(out)) throw InputError(out, "no such output folder");
  if (!quiet) std::printf("drawing charts and report.html\n");
  report_html(out);  // reads every result file: a damaged one fails before any chart is drawn
  if (write_charts(out).gnuplot_missing)
    std::fprintf(stderr, "warning: gnuplot not found, no charts drawn (install gnuplot-nox)\n");
  const std::filesystem::path report = write_report(out);
  if (!quiet) std::printf("report: %s\n", report.string().c_str());
  return 0;
}

}  // namespace splat::cli
