#pragma once
// splat-render: renders every frame of a transforms JSON to PNG, or a fly-through along a
// camera path to a video and/or PNGs (docs/DESIGN.md contract).
#include <filesystem>
#include <optional>
#include <string>
#include <variant>

#include "splat/gaussians/gaussian_model.hpp"
#include "splat/nerf/nerf_model.hpp"
#include "splat/raster/rasterizer.hpp"

namespace splat::cli {

// The camera path of a fly-through (--path); kNone renders the --cameras views themselves.
enum class CameraPathKind { kNone, kOrbit, kSpiral, kInterpolate };

struct RenderCommandOptions {
  std::filesystem::path model;     // .ply, .splat, .spz, .nerf or .ngp
  std::filesystem::path cameras;   // transforms JSON (optional with a path, except interpolate)
  std::filesystem::path out;       // output folder, created if missing (optional with --video)
  int width = 0, height = 0;       // 0: the dataset's image size, else 800 x 800
  float background[3] = {1, 1, 1};
  int sh_degree = 3;               // clamped to the model's
  int bench_repeats = 0;           // > 0: time each frame this many times after a warm-up
  int bits = 8;                    // PNG bits per channel
  CameraPathKind path = CameraPathKind::kNone;
  int frames = 120;                // frames along the path
  std::filesystem::path video;     // empty: no video
  double fps = 30;                 // the video's frame rate
  bool quiet = false;              // no progress lines (splat-eval's fly-throughs)
};

// A model splat-render draws: Gaussians or a NeRF.
using RenderModel = std::variant<GaussianModel, NerfModel>;

// The one place splat-render reads a model: the format from the extension (.ply, .splat,
// .spz, .nerf, .ngp);
// InputError naming the file for a folder, another extension, or a file its reader refuses.
RenderModel load_model(const std::filesystem::path& file);

// Creates `folder` and its parents if missing; InputError naming it when that fails.
void create_output_folder(const std::filesystem::path& folder);

// The rasterizer's settings for these options (SH degree, background, no backward).
RenderSettings render_settings(const RenderCommandOptions& options);

// Runs the command; prints progress, and with bench_repeats the timing JSON last.
int run_render_command(const RenderCommandOptions& options);

}  // namespace splat::cli
