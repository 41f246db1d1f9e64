// splat-eval --data DIR --out DIR [--max-seconds S] [--stability | --sweep-gaussians N,N,...]
//            [--threads N] [--eval-every-seconds T] [--bg white|black] ...
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "common/arg_parser.hpp"
#include "common/run_main.hpp"
#include "config_file.hpp"
#include "eval_command.hpp"
#include "splat/core/error.hpp"

namespace {

constexpr const char* kUsage = R"(usage: splat-eval --data DIR --out DIR [options]

Trains the Gaussian splats and then the NeRF on one dataset, each for the same wall-clock
budget and with the same threads, scoring the test views at regular points of training time
(scoring time is not counted against the budget, and is reported). Then renders the test views
with both final models, timing each render. Writes into --out:
  results.json          per method: history [{seconds, iteration, test_psnr, test_ssim}],
                        final {psnr, ssim}, num_gaussians (splat), num_params, model_bytes,
                        train_seconds, render_ms_per_view_median, model_file; plus the
                        dataset, budget and threads
  splat/model.ply, splat/test/<view>.png, nerf/model.nerf, nerf/test/<view>.png
  grids/<view>.png      ground truth | splat | NeRF | splat error | NeRF error; an error map
                        is grey min(1, 4 * mean over RGB of |render - truth|)
  charts/*.{png,svg}    drawn by gnuplot: PSNR and SSIM over training time, PSNR against
                        model bytes, render time against PSNR (and the runs below)
  report.html           the tables, charts and grids on one offline page

With --stability, instead: both methods under each condition (all training views; only 8,
16, 32 of them; training poses turned 0.25/1/3 degrees and moved 0.25/1/3 % of the scene
extent; random initialisation when the data has a point cloud), each trained S seconds and
scored once, into stability.json (PSNR, SSIM, time, model size and a verdict per run:
diverged, collapsed = no better than the background alone + 1 dB, degraded = over 3 dB below
the method's all-views run, else ok) and stability/<condition>/<method>/.

With --sweep-gaussians N,N,..., instead: the splat method under each Gaussian budget for S
seconds, into sweep.json (PSNR, Gaussians, bytes, render time; the smallest model within
0.5 dB of the best is marked) and sweep/<N>/.

Each run redraws the charts and report.html from every result file in --out, so the three
can share one folder and one report. --report (with --out only) just redraws them.

  --data DIR                  Blender/NeRF-synthetic or COLMAP folder (as splat-train)
  --out DIR                   output folder (created if missing)
  --max-seconds S             training budget per run in seconds (default 600)
  --stability                 run the stability conditions (see above)
  --stability-views N,N,...   training views kept in the fewer-views conditions (default 8,16,32)
  --sweep-gaussians N,N,...   run the Gaussian budget sweep with these budgets
  --eval-every-seconds T      score the test views every T seconds of training (default S/10)
  --threads N                 worker threads for both methods (default: all cores)
  --bg white|black            background the RGBA images are composited onto (default white)
  --downscale K               train and evaluate at 1/K of the image size (default 1)
  --splat-config FILE         JSON settings for the splat trainer (as splat-train --config)
  --nerf-config FILE          JSON settings for the NeRF trainer (as splat-train --config)
  --report                    only redraw the charts and report.html in --out
  --quiet                     no progress output
)";

// "8,16,32": each a whole number >= 1.
template <class Integer>
std::vector<Integer> positive_list(const std::string& text, const std::string& option) {
  std::vector<Integer> values;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find(',', start), text.size());
    const std::string word = text.substr(start, end - start);
    char* rest = nullptr;
    const long long value = std::strtoll(word.c_str(), &rest, 10);
    if (word.empty() || *rest != '\0' || value < 1 || value > 1000000000)
      throw splat::ArgumentError(option + " expects whole numbers >= 1 separated by commas, got '" + text + "'");
    values.push_back(Integer(value));
    start = end + 1;
  }
  return values;
}

}  // namespace

int main(int argc, char** argv) {
  return splat::cli::run_main([&] {
    splat::cli::ArgParser args(argc, argv,
                               {"data", "out", "max-seconds", "eval-every-seconds", "threads", "bg",
                                "downscale", "splat-config", "nerf-config", "sweep-gaussians",
                                "stability-views"},
                               {"help", "quiet", "stability", "report"});
    if (args.has("help")) {
      std::fputs(kUsage, stdout);
      return 0;
    }
    args.expect_no_positionals();
    if (args.has("report")) return splat::cli::redraw_report(args.required("out"), args.has("quiet"));
    splat::cli::EvalCommandOptions options;
    options.data = args.required("data");
    options.out = args.required("out");
    if (auto file = args.value("splat-config")) splat::cli::read_config_file(*file, options.splat_config);
    if (auto file = args.value("nerf-config")) splat::cli::read_config_file(*file, options.nerf_config);
    if (auto s = args.number("max-seconds")) {
      if (*s <= 0) throw splat::ArgumentError("--max-seconds must be > 0");
      options.max_seconds = *s;
    }
    if (auto t = args.number("eval-every-seconds")) {
      if (*t <= 0) throw splat::ArgumentError("--eval-every-seconds must be > 0");
      options.eval_every = *t;
    }
    if (auto n = args.positive_integer("threads")) options.threads = *n;
    if (auto k = args.positive_integer("downscale")) options.dataset.downscale = *k;
    const std::string bg = args.value("bg").value_or("white");
    if (bg != "white" && bg != "black") throw splat::ArgumentError("--bg must be white or black");
    const float value = bg == "white" ? 1.0f : 0.0f;
    for (int c = 0; c < 3; ++c)
      options.dataset.background[c] = options.splat_config.background[c] = options.nerf_config.background[c] = value;
    // The budget is the only limit that matters here; splat-eval runs its own loop.
    options.splat_config.test_interval = options.nerf_config.test_interval = 0;
    options.splat_config.checkpoint_interval = options.nerf_config.checkpoint_interval = 0;
    options.quiet = args.has("quiet");
    if (args.has("stability") && args.value("sweep-gaussians"))
      throw splat::ArgumentError("--stability and --sweep-gaussians are separate runs; give one");
    if (args.has("stability")) options.mode = splat::cli::EvalMode::kStability;
    if (auto list = args.value("stability-views")) options.stability_views = positive_list<int>(*list, "--stability-views");
    if (auto list = args.value("sweep-gaussians")) {
      options.mode = splat::cli::EvalMode::kGaussianSweep;
      options.sweep_gaussians = positive_list<std::size_t>(*list, "--sweep-gaussians");
    }
    return splat::cli::run_eval_command(options);
  });
}
