// splat-eval --data DIR --out DIR [--max-seconds S] [--threads N] [--eval-every-seconds T]
//            [--bg white|black] ...
#include <cstdio>
#include <fstream>

#include "common/arg_parser.hpp"
#include "common/run_main.hpp"
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
  charts/{psnr,ssim}_vs_time.{png,svg}   test scores over training time (gnuplot)

  --data DIR                  Blender/NeRF-synthetic or COLMAP folder (as splat-train)
  --out DIR                   output folder (created if missing)
  --max-seconds S             training budget per method in seconds (default 600)
  --eval-every-seconds T      score the test views every T seconds of training (default S/10)
  --threads N                 worker threads for both methods (default: all cores)
  --bg white|black            background the RGBA images are composited onto (default white)
  --downscale K               train and evaluate at 1/K of the image size (default 1)
  --splat-config FILE         JSON settings for the splat trainer (as splat-train --config)
  --nerf-config FILE          JSON settings for the NeRF trainer (as splat-train --config)
  --quiet                     no progress output
)";

template <class Config>
void read_config(const std::string& file, Config& config) {
  std::ifstream in(file);
  if (!in) throw splat::InputError(file, "cannot open the config file");
  try {
    splat::from_json(nlohmann::json::parse(in), config);
  } catch (const nlohmann::json::exception& e) {
    throw splat::InputError(file, std::string("malformed JSON: ") + e.what());
  } catch (const splat::ArgumentError& e) {
    throw splat::InputError(file, e.what());
  }
}

}  // namespace

int main(int argc, char** argv) {
  return splat::cli::run_main([&] {
    splat::cli::ArgParser args(argc, argv,
                               {"data", "out", "max-seconds", "eval-every-seconds", "threads", "bg",
                                "downscale", "splat-config", "nerf-config"},
                               {"help", "quiet"});
    if (args.has("help")) {
      std::fputs(kUsage, stdout);
      return 0;
    }
    if (!args.positionals().empty())
      throw splat::ArgumentError("unexpected argument '" + args.positionals().front() + "'");
    splat::cli::EvalCommandOptions options;
    options.data = args.required("data");
    options.out = args.required("out");
    if (auto file = args.value("splat-config")) read_config(*file, options.splat_config);
    if (auto file = args.value("nerf-config")) read_config(*file, options.nerf_config);
    if (auto s = args.number("max-seconds")) {
      if (*s <= 0) throw splat::ArgumentError("--max-seconds must be > 0");
      options.max_seconds = *s;
    }
    if (auto t = args.number("eval-every-seconds")) {
      if (*t <= 0) throw splat::ArgumentError("--eval-every-seconds must be > 0");
      options.eval_every = *t;
    }
    if (auto n = args.integer("threads")) {
      if (*n < 1) throw splat::ArgumentError("--threads must be >= 1");
      options.threads = *n;
    }
    if (auto k = args.integer("downscale")) {
      if (*k < 1) throw splat::ArgumentError("--downscale must be >= 1");
      options.dataset.downscale = *k;
    }
    const std::string bg = args.value("bg").value_or("white");
    if (bg != "white" && bg != "black") throw splat::ArgumentError("--bg must be white or black");
    const float value = bg == "white" ? 1.0f : 0.0f;
    for (int c = 0; c < 3; ++c)
      options.dataset.background[c] = options.splat_config.background[c] = options.nerf_config.background[c] = value;
    // The budget is the only limit that matters here; splat-eval runs its own loop.
    options.splat_config.test_interval = options.nerf_config.test_interval = 0;
    options.splat_config.checkpoint_interval = options.nerf_config.checkpoint_interval = 0;
    options.quiet = args.has("quiet");
    return splat::cli::run_eval_command(options);
  });
}
