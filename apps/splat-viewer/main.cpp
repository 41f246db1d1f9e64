// splat-viewer FILE [FILE2] [--cameras TRANSFORMS.json --view K] [--width W --height H]
//              [--screenshot PNG] ...
#include <cstdio>

#include "apps/common/arg_parser.hpp"
#include "apps/common/run_main.hpp"
#include "apps/common/training_cameras.hpp"
#include "apps/splat-viewer/panel_model.hpp"
#include "splat/core/error.hpp"
#include "apps/splat-viewer/viewer_app.hpp"
#include "apps/splat-viewer/watched_model.hpp"

namespace {

constexpr splat::SettingRange kWindowSideRange{16, 8192};

constexpr const char* kUsage = R"(usage: splat-viewer FILE [FILE2] [options]
       splat-viewer --watch DIR [options]

Shows a Gaussian model (.ply, .splat, .spz) or a NeRF (.nerf, .ngp) in a window, rendered by the CPU rasterizer
(or the NeRF renderer) every frame; with two files, both side by side under one camera.
With --watch, the model a running splat-train writes into DIR (its --out folder, trained
with --snapshot-every S), followed as it improves: the newest of DIR/snapshot.ply and
DIR/model.ply (or .nerf, .ngp), looked for twice a second; waits up to 10 minutes for the first.

Controls: left drag orbit, right/middle drag pan, scroll zoom, W A S D Q E fly, R reset,
[ ] dataset views, + - SH degree, B background, P screenshot, H help, Esc quit.

  --watch DIR           follow a running training's model (see above)
  --cameras FILE        transforms JSON: start at its view, step through them with [ ]
                        (default: the cameras_train.json splat-train wrote beside the
                        (first) model or in the --watch folder, when it is there)
  --view K              the view of --cameras to start at (default 0)
  --width W --height H  size of one panel (default: the cameras' image size, else 800x600)
  --bg COLOUR           background: white, black or R,G,B in [0, 1] (default white)
  --sh-degree N         SH degree to start with, 0..3 (default 3)
  --fps F               frame rate reduced resolution aims to hold while moving (default 30)
  --screenshot PNG      draw the view at full resolution, save the window to PNG, exit 0
  --screenshot-overlay  with --screenshot: include the on-screen overlay
  --show-help           start with the help overlay open
  --bench-orbit S       orbit S seconds each at full resolution, at half resolution and
                        adaptive (--fps); print the frame rates as JSON and exit
)";

}  // namespace

int main(int argc, char** argv) {
  return splat::cli::run_main([&] {
    splat::cli::ArgParser args(argc, argv,
                               {"cameras", "view", "width", "height", "bg", "sh-degree", "fps", "screenshot",
                                "bench-orbit", "watch"},
                               {"help", "screenshot-overlay", "show-help"});
    if (args.has("help")) {
      std::fputs(kUsage, stdout);
      return 0;
    }
    const auto& files = args.positionals();
    const std::optional<std::string> watch = args.value("watch");
    if (watch && !files.empty())
      throw splat::ArgumentError("--watch shows the model in its folder; give no model files with it");
    if (!watch && (files.empty() || files.size() > 2))
      throw splat::ArgumentError("expected one or two model files, got " + std::to_string(args.positionals().size()) +
                                 " (see --help)");
    splat::viewer::ViewerOptions options;
    options.files.assign(files.begin(), files.end());
    if (watch) options.files = {*watch};

    const auto width = args.integer("width", kWindowSideRange), height = args.integer("height", kWindowSideRange);
    if (width.has_value() != height.has_value()) throw splat::ArgumentError("give both --width and --height, or neither");
    std::optional<std::string> cameras_file = args.value("cameras");
    if (!cameras_file) {
      // The views the model trained on, when the run left them beside it.
      const std::filesystem::path folder =
          watch ? std::filesystem::path(*watch) : std::filesystem::path(files.front()).parent_path();
      if (auto beside = splat::cli::announced_training_cameras(folder)) cameras_file = beside->string();
    }
    if (auto file = cameras_file) {
      splat::TransformsOptions transforms;
      if (width) transforms.width = *width, transforms.height = *height;
      options.cameras = splat::load_transforms(*file, transforms);
      options.view = args.integer("view", splat::cli::kViewIndexRange).value_or(0);
      if (options.view < 0 || options.view >= int(options.cameras.size()))
        throw splat::ArgumentError("--view " + std::to_string(options.view) + " is out of range: " + *file + " has " +
                                   std::to_string(options.cameras.size()) + " views");
      options.width = options.cameras.front().camera.width;
      options.height = options.cameras.front().camera.height;
    } else if (args.value("view")) {
      throw splat::ArgumentError("--view needs --cameras");
    }
    if (width) options.width = *width, options.height = *height;
    const std::array<float, 3> bg = args.colour("bg").value_or(std::array<float, 3>{1, 1, 1});
    std::copy(bg.begin(), bg.end(), options.settings.background);
    if (auto n = args.integer("sh-degree", splat::cli::kShDegreeRange)) options.settings.sh_degree = *n;
    if (auto f = args.number("fps", {1, 240})) options.target_fps = *f;
    if (auto s = args.value("screenshot")) options.screenshot = *s;
    options.screenshot_overlay = args.has("screenshot-overlay");
    if (options.screenshot_overlay && !args.value("screenshot"))
      throw splat::ArgumentError("--screenshot-overlay goes with --screenshot FILE, which is missing");
    options.show_help = args.has("show-help");
    if (auto s = args.number("bench-orbit", {0.1, 3600})) options.bench_seconds = *s;

    // Every model loads before a window opens: bad input never leaves one behind.
    std::vector<std::unique_ptr<splat::viewer::PanelModel>> models;
    if (watch) {
      constexpr double kFirstModelWaitSeconds = 600;
      splat::viewer::wait_for_first_model(*watch, kFirstModelWaitSeconds);
      auto watched = std::make_unique<splat::viewer::WatchedModel>(*watch);
      splat::viewer::WatchedModel* follow = watched.get();
      models.push_back(std::move(watched));
      return splat::viewer::run_viewer(options, std::move(models), follow);
    }
    for (const auto& file : options.files) models.push_back(splat::viewer::load_panel_model(file));
    return splat::viewer::run_viewer(options, std::move(models));
  });
}
