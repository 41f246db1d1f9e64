#pragma once
// splat-render: renders every frame of a transforms JSON to PNG (docs/DESIGN.md contract).
#include <filesystem>
#include <optional>
#include <string>

namespace splat::cli {

struct RenderCommandOptions {
  std::filesystem::path model;     // .ply, .splat, .spz or .nerf
  std::filesystem::path cameras;   // transforms JSON
  std::filesystem::path out;       // output folder, created if missing
  int width = 0, height = 0;       // 0: the dataset's image size, else 800 x 800
  float background[3] = {1, 1, 1};
  int sh_degree = 3;               // clamped to the model's
  int bench_repeats = 0;           // > 0: time each frame this many times after a warm-up
  int bits = 8;                    // PNG bits per channel
};

// Runs the command; prints progress, and with bench_repeats the timing JSON last.
int run_render_command(const RenderCommandOptions& options);

}  // namespace splat::cli
