// splat-eval --data DIR --out DIR [--methods LIST] [--max-seconds S]
//            [--stability | --sweep-gaussians N,N,...] [--threads N] [--eval-every-seconds T] ...
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "apps/common/arg_parser.hpp"
#include "apps/common/run_main.hpp"
#include "apps/common/video_writer.hpp"
#include "splat/train/config_file.hpp"
#include "apps/splat-eval/eval_command.hpp"
#include "apps/splat-eval/eval_methods.hpp"  // read_splat_settings
#include "splat/core/error.hpp"

namespace {

constexpr const char* kUsage = R"(usage: splat-eval --data DIR --out DIR [options]

Trains each method in turn on one dataset, each for the same budget of training time (wall
clock minus scoring, which is reported) and with the same threads, scoring the test views at
regular points of training time. Then renders the test views with every final model, timing
each render. The methods (--methods, in that order; default all four):
  splat                 Gaussian splatting with the compact density strategy
  splat-official        Gaussian splatting with the official 3DGS density control
  nerf                  the NeRF baseline (MLPs on a positional encoding)
  ngp                   the NeRF with Instant-NGP's multiresolution hash encoding
Writes into --out:
  results.json          per method: method, strategy (splat methods), history [{seconds,
                        iteration, test_psnr, test_ssim, num_gaussians, model_bytes}], final
                        {psnr, ssim}, num_gaussians (splat methods), num_params, model_bytes,
                        train_seconds, render_ms_per_view_median, model_file; plus the
                        dataset, budget and threads
  <method>/model.ply, model.nerf or model.ngp, <method>/test/<view>.png: one folder per method
  grids/<view>.png      ground truth | each method | each method's error; an error map is
                        grey min(1, 4 * mean over RGB of |render - truth|)
  charts/*.{png,svg}    drawn by gnuplot, a curve per method: PSNR and SSIM over training
                        time, PSNR against model bytes and against Gaussians, render time
                        against PSNR (and the runs below)
  report.html           the tables, charts and grids on one offline page

With --stability, instead: the methods (default splat and nerf) under each condition (all
training views; only 8, 16, 32 of them; training poses turned 0.25/1/3 degrees and moved
0.25/1/3 % of the scene extent; random initialisation when the data has a point cloud; and,
for the splat methods only, all views and each pose noise level again with --refine-poses,
whose test views are carried into the model's frame by the similarity the training poses
moved by and aligned to their photographs with the model fixed before they are scored),
each trained S seconds and scored once, into stability.json (PSNR, SSIM, time, model size
and a verdict per run: diverged, collapsed = no better than the background alone + 1 dB,
failed = below the absolute floor, the higher of the background alone + 3 dB and 20 dB
(whatever the baseline), degraded = over 3 dB below the method's all-views run, else ok; for a refined run also its
training cameras' error against the true poses, before and after, once a similarity is
fitted) and stability/<condition>/<method>/ (each run's cameras_train.json there: a refined run's
training cameras as trained).

With --sweep-gaussians N,N,..., instead: one splat method (splat, i.e. compact, unless
--methods splat-official) under each Gaussian budget for S seconds, into sweep.json (PSNR,
Gaussians, bytes, render time; the smallest model within 0.5 dB of the best is marked) and
sweep/<N>/.

Each run redraws the charts and report.html from every result file in --out, so the three
can share one folder and one report. --report (with --out only) just redraws them.

  --data DIR                  Blender/NeRF-synthetic or COLMAP folder (as splat-train)
  --out DIR                   output folder (created if missing)
  --methods LIST              comma-separated methods to run, from splat, splat-official, nerf,
                              ngp
  --max-seconds S             training budget per run in seconds (default 600)
  --stability                 run the stability conditions (see above)
  --stability-views N,N,...   training views kept in the fewer-views conditions (default 8,16,32)
  --stability-conditions L    the kinds of condition to run, from baseline, views, pose-noise,
                              refinement, random-init (default all)
  --pose-noise D,D,...        pose noise levels: D degrees and D % of the scene extent
                              (default 0.25,1,3)
  --sweep-gaussians N,N,...   run the Gaussian budget sweep with these budgets
  --eval-every-seconds T      score the test views every T seconds of training (default S/10)
  --threads N                 worker threads for every method (default: all cores)
  --bg COLOUR                 background the RGBA images are composited onto: white, black or
                              R,G,B in [0, 1] (default white)
  --downscale K               train and evaluate at 1/K of the image size (default: 1, or
                              the smallest K that brings images wider than 1,600 pixels to
                              1,600 at most, as the official trainer does)
  --splat-config FILE         JSON settings for both splat methods (as splat-train --config),
                              applied over each one's strategy preset; a "strategy" key in it
                              is ignored (with a warning): the method names the strategy
  --nerf-config FILE          JSON settings for the NeRF trainer (as splat-train --config)
  --ngp-config FILE           JSON settings for the NGP trainer (as splat-train --method ngp
                              --config)
  --fly-through N             after training, each method's orbit of N frames around the
                              training views' centre, OUT/<method>/orbit.mp4 (ffmpeg), shown
                              side by side in the report (the comparison only)
  --report                    only redraw the charts and report.html in --out
  --quiet                     no progress output
)";

}  // namespace

int main(int argc, char** argv) {
  return splat::cli::run_main([&] {
    splat::cli::ArgParser args(argc, argv,
                               {"data", "out", "methods", "max-seconds", "eval-every-seconds", "threads",
                                "bg", "downscale", "splat-config", "nerf-config", "ngp-config", "sweep-gaussians",
                                "stability-views", "stability-conditions", "pose-noise", "fly-through"},
                               {"help", "quiet", "stability", "report"});
    if (args.has("help")) {
      std::fputs(kUsage, stdout);
      return 0;
    }
    args.expect_no_positionals();
    if (args.has("report")) {
      // The report is redrawn from the result files in --out alone: an option that would
      // change a run is a mistake, not something to ignore.
      for (const char* option : {"data", "methods", "max-seconds", "eval-every-seconds", "downscale", "splat-config",
                                 "nerf-config", "ngp-config", "sweep-gaussians", "stability-views", "stability-conditions",
                                 "pose-noise", "fly-through", "bg"})
        if (args.value(option))
          throw splat::ArgumentError(std::string("--report redraws the report from --out alone; --") + option +
                                     " is for a run");
      if (args.has("stability")) throw splat::ArgumentError("--report redraws the report from --out alone; --stability is for a run");
      return splat::cli::redraw_report(args.required("out"), args.has("quiet"));
    }
    splat::cli::EvalCommandOptions options;
    options.data = args.required("data");
    options.out = args.required("out");
    if (auto list = args.words("methods")) options.methods = *list;  // checked by the run
    if (auto file = args.value("splat-config")) options.splat_settings = splat::cli::read_splat_settings(*file);
    if (auto file = args.value("nerf-config")) splat::read_config_file(*file, options.nerf_config);
    if (auto file = args.value("ngp-config")) splat::read_config_file(*file, options.ngp_config);
    if (auto s = args.number("max-seconds", {0.01, splat::kMaxTrainingSeconds})) options.max_seconds = *s;
    if (auto t = args.number("eval-every-seconds", {0.01, splat::kMaxTrainingSeconds})) options.eval_every = *t;
    if (auto n = args.integer("threads", splat::cli::kThreadsRange)) options.threads = *n;
    if (auto k = args.integer("downscale", splat::kDownscaleRange)) options.dataset.downscale = *k;
    else options.dataset.max_width = splat::kDefaultMaxImageWidth;
    const std::array<float, 3> bg = args.colour("bg").value_or(std::array<float, 3>{1, 1, 1});
    std::copy(bg.begin(), bg.end(), options.dataset.background);  // and the trainers'
    options.quiet = args.has("quiet");
    if (auto frames = args.integer("fly-through", {1, 100000})) {
      if (args.has("stability") || args.value("sweep-gaussians"))
        throw splat::ArgumentError("--fly-through is for the comparison; not with --stability or --sweep-gaussians");
      // Known before anything trains: the videos are the run's last step.
      if (!splat::cli::find_ffmpeg())
        throw splat::Error("--fly-through encodes with ffmpeg, which is not installed (apt-get install ffmpeg)");
      options.fly_through_frames = *frames;
    }
    if (args.has("stability") && args.value("sweep-gaussians"))
      throw splat::ArgumentError("--stability and --sweep-gaussians are separate runs; give one");
    if (args.has("stability")) options.mode = splat::cli::EvalMode::kStability;
    if (auto list = args.integer_list("stability-views", {1, splat::kMaxViews}))
      options.stability_views.assign(list->begin(), list->end());
    if (auto list = args.words("stability-conditions")) {
      options.stability_kinds = *list;
      for (const std::string& kind : options.stability_kinds)
        if (std::find(std::begin(splat::cli::kStabilityKinds), std::end(splat::cli::kStabilityKinds), kind) ==
            std::end(splat::cli::kStabilityKinds))
          throw splat::ArgumentError("--stability-conditions: unknown kind '" + kind +
                                     "' (baseline, views, pose-noise, refinement, random-init)");
    }
    if (auto list = args.number_list("pose-noise", {0.01, 90})) {
      options.pose_noise_levels.clear();
      for (const double degrees : *list) options.pose_noise_levels.push_back({degrees, degrees / 100.0});
    }
    if ((args.value("stability-conditions") || args.value("pose-noise") || args.value("stability-views")) &&
        !args.has("stability"))
      throw splat::ArgumentError("--stability-conditions, --pose-noise and --stability-views need --stability");
    if (auto list = args.value("sweep-gaussians")) {
      options.mode = splat::cli::EvalMode::kGaussianSweep;
      const auto budgets = *args.integer_list("sweep-gaussians", {1, splat::kMaxGaussiansSetting});
      options.sweep_gaussians.assign(budgets.begin(), budgets.end());
    }
    return splat::cli::run_eval_command(options);
  });
}
