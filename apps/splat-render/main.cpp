// splat-render --model FILE --cameras TRANSFORMS.json --out DIR [--width W --height H]
//              [--bg COLOUR] [--bench N] [--sh-degree D] [--threads N] [--png16]
// splat-render --model FILE --path orbit|spiral|interpolate [--frames N] [--video OUT.mp4]
//              [--out DIR] [--cameras TRANSFORMS.json] [--fps F] ...
#include <cstdio>
#include <memory>
#include <string>
#include <tbb/global_control.h>

#include "apps/common/arg_parser.hpp"
#include "apps/common/run_main.hpp"
#include "apps/common/render_command.hpp"
#include "apps/common/training_cameras.hpp"
#include "splat/core/error.hpp"
#include "splat/train/trainer_adapter.hpp"

namespace {

// Above these a fly-through is a mistake rather than a video: an hour at 30 fps, and
// faster than any display.
constexpr int kMaxPathFrames = 100000;
constexpr double kMaxFps = 240;

constexpr const char* kUsage = R"(usage: splat-render --model FILE --cameras TRANSFORMS.json --out DIR
                    [--width W --height H] [--bg COLOUR] [--bench N]
                    [--sh-degree D] [--threads N] [--png16]
       splat-render --model FILE --path orbit|spiral|interpolate [--frames N]
                    [--video OUT.mp4] [--out DIR] [--cameras TRANSFORMS.json] [--fps F]
                    [--width W --height H] [--bg COLOUR] [--sh-degree D] [--threads N] [--png16]

Renders every frame of a Blender/NeRF-synthetic transforms JSON with the CPU Gaussian
rasterizer (or a NeRF's renderer) and writes <out>/<frame name>.png; or, with --path, a
fly-through: N frames along a camera path, as a video and/or <out>/frame_0000.png ...

  --model FILE        Gaussian model (.ply, .splat, .spz) or NeRF (.nerf or .ngp, from
                      splat-train --method nerf or ngp)
  --cameras FILE      transforms JSON (camera_angle_x or fl_x/fl_y/cx/cy, transform_matrix);
                      with --path orbit/spiral, the circle follows these cameras (their
                      centre, distance, height, up and field of view); with --path and no
                      --cameras, the cameras_train.json that splat-train wrote beside the
                      model, when it is there
  --out DIR           output folder (created if missing); with --path optional when
                      --video is given (frames are written as frame_0000.png ...)
  --width, --height   image size (default: the dataset's images, else 800x800; for a video,
                      sizes must be even: a default one is rounded down, a given one refused)
  --path NAME         fly-through: orbit (one turn round the model, framed from its
                      Gaussians, opacity-weighted so floaters do not count, or a NeRF's box,
                      world z up; or following the --cameras: their centre, distance, height,
                      up and field of view), spiral (the orbit swinging 30 deg above and below
                      it), interpolate (through the --cameras views in file order; needs them)
  --frames N          frames along the path, 1..100000 (default 120)
  --video FILE        encode the path's frames with ffmpeg (must be installed): .mp4 or .mkv
                      (H.264), .webm (VP9); written whole or not at all
  --fps F             the video's frame rate, up to 240 (default 30)
  --bg COLOUR         background: white, black or R,G,B in [0, 1] (default white)
  --sh-degree D       spherical-harmonic bands to use, 0..3 (default: all the model has)
  --bench N           render each frame N more times after a warm-up; print the median
                      ms per frame and its breakdown; the last line is a JSON object
  --threads N         worker threads (default: all cores); the images do not depend on it
  --png16             write 16-bit PNGs (default 8-bit)
)";

// Fly-through options per the usage text: --path and what goes with it, each checked here.
void read_path_options(const splat::cli::ArgParser& args, splat::cli::RenderCommandOptions& options) {
  using splat::ArgumentError;
  using splat::cli::CameraPathKind;
  const auto path = args.value("path");
  if (!path) {
    for (const char* name : {"frames", "video", "fps"})
      if (args.has(name)) throw ArgumentError(std::string("--") + name + " goes with --path (see --help)");
    return;
  }
  if (*path == "orbit") options.path = CameraPathKind::kOrbit;
  else if (*path == "spiral") options.path = CameraPathKind::kSpiral;
  else if (*path == "interpolate") options.path = CameraPathKind::kInterpolate;
  else throw ArgumentError("--path must be orbit, spiral or interpolate, not '" + *path + "'");
  options.frames = args.integer("frames", {1, kMaxPathFrames}).value_or(options.frames);
  options.video = args.value("video").value_or("");
  options.fps = args.number("fps", {0.01, kMaxFps}).value_or(options.fps);
  if (options.video.empty() && !args.has("out"))
    throw ArgumentError("--path writes a --video, PNGs into --out, or both: give at least one");
  if (args.has("bench")) throw ArgumentError("--bench times the --cameras views; it does not go with --path");
}

}  // namespace

int main(int argc, char** argv) {
  return splat::cli::run_main([&] {
    splat::cli::ArgParser args(argc, argv,
                               {"model", "cameras", "out", "width", "height", "bg", "bench",
                                "sh-degree", "threads", "path", "frames", "video", "fps"},
                               {"help", "png16"});
    if (args.has("help")) {
      std::fputs(kUsage, stdout);
      return 0;
    }
    args.expect_no_positionals();
    splat::cli::RenderCommandOptions options;
    options.model = args.required("model");
    read_path_options(args, options);
    if (options.path == splat::cli::CameraPathKind::kNone) {
      options.cameras = args.required("cameras");
      options.out = args.required("out");
    } else {
      options.cameras = args.value("cameras").value_or("");
      options.out = args.value("out").value_or("");
      if (options.cameras.empty()) {
        if (auto beside = splat::cli::announced_training_cameras(options.model.parent_path())) {
          options.cameras = *beside;
        } else if (options.path == splat::cli::CameraPathKind::kInterpolate) {
          throw splat::ArgumentError("--path interpolate goes through the views of --cameras, which is missing (and no " +
                                     std::string(splat::kTrainCamerasFileName) + " is beside the model)");
        }
      }
    }
    options.width = args.integer("width", splat::cli::kImageSideRange).value_or(0);
    options.height = args.integer("height", splat::cli::kImageSideRange).value_or(0);
    if ((options.width > 0) != (options.height > 0))
      throw splat::ArgumentError("give both --width and --height, or neither");
    if (auto bg = args.colour("bg"))
      for (int c = 0; c < 3; ++c) options.background[c] = (*bg)[c];
    options.sh_degree = args.integer("sh-degree", splat::cli::kShDegreeRange).value_or(3);
    options.bench_repeats = args.integer("bench", {1, 100000}).value_or(0);
    if (args.has("png16")) options.bits = 16;
    std::unique_ptr<tbb::global_control> threads;
    if (auto n = args.integer("threads", splat::cli::kThreadsRange)) {
      threads = std::make_unique<tbb::global_control>(
          tbb::global_control::max_allowed_parallelism, std::size_t(*n));
    }
    return splat::cli::run_render_command(options);
  });
}
