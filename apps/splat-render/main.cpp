// splat-render --model FILE --cameras TRANSFORMS.json --out DIR [--width W --height H]
//              [--bg R,G,B] [--bench N] [--sh-degree D] [--threads N] [--png16]
#include <cstdio>
#include <memory>
#include <tbb/global_control.h>

#include "apps/common/arg_parser.hpp"
#include "apps/common/run_main.hpp"
#include "apps/splat-render/render_command.hpp"
#include "splat/core/error.hpp"

namespace {

constexpr const char* kUsage = R"(usage: splat-render --model FILE --cameras TRANSFORMS.json --out DIR
                    [--width W --height H] [--bg R,G,B] [--bench N]
                    [--sh-degree D] [--threads N] [--png16]

Renders every frame of a Blender/NeRF-synthetic transforms JSON with the CPU Gaussian
rasterizer and writes <out>/<frame name>.png.

  --model FILE        Gaussian model (.ply, .splat, .spz) or NeRF (.nerf, from splat-train
                      --method nerf)
  --cameras FILE      transforms JSON (camera_angle_x or fl_x/fl_y/cx/cy, transform_matrix)
  --out DIR           output folder (created if missing)
  --width, --height   image size (default: the dataset's images, else 800x800)
  --bg R,G,B          background colour in [0,1] (default 1,1,1)
  --sh-degree D       spherical-harmonic bands to use, 0..3 (default: all the model has)
  --bench N           render each frame N more times after a warm-up; print the median
                      ms per frame and its breakdown; the last line is a JSON object
  --threads N         worker threads (default: all cores); the images do not depend on it
  --png16             write 16-bit PNGs (default 8-bit)
)";

}  // namespace

int main(int argc, char** argv) {
  return splat::cli::run_main([&] {
    splat::cli::ArgParser args(argc, argv,
                               {"model", "cameras", "out", "width", "height", "bg", "bench",
                                "sh-degree", "threads"},
                               {"help", "png16"});
    if (args.has("help")) {
      std::fputs(kUsage, stdout);
      return 0;
    }
    args.expect_no_positionals();
    splat::cli::RenderCommandOptions options;
    options.model = args.required("model");
    options.cameras = args.required("cameras");
    options.out = args.required("out");
    options.width = args.integer("width").value_or(0);
    options.height = args.integer("height").value_or(0);
    if (options.width < 0 || options.height < 0 || options.width > 16384 || options.height > 16384)
      throw splat::ArgumentError("--width/--height must be in 1..16384");
    if ((options.width > 0) != (options.height > 0))
      throw splat::ArgumentError("give both --width and --height, or neither");
    if (auto bg = args.float_list("bg", 3)) {
      for (int c = 0; c < 3; ++c) {
        if ((*bg)[c] < 0 || (*bg)[c] > 1)
          throw splat::ArgumentError("--bg components must be in [0, 1]");
        options.background[c] = (*bg)[c];
      }
    }
    options.sh_degree = args.integer("sh-degree").value_or(3);
    if (options.sh_degree < 0 || options.sh_degree > 3)
      throw splat::ArgumentError("--sh-degree must be 0..3");
    options.bench_repeats = args.integer("bench").value_or(0);
    if (options.bench_repeats < 0) throw splat::ArgumentError("--bench must be >= 0");
    if (args.has("png16")) options.bits = 16;
    std::unique_ptr<tbb::global_control> threads;
    if (auto n = args.positive_integer("threads")) {
      threads = std::make_unique<tbb::global_control>(
          tbb::global_control::max_allowed_parallelism, std::size_t(*n));
    }
    return splat::cli::run_render_command(options);
  });
}
