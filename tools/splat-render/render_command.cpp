#include "splat-render/render_command.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

#include "splat/core/error.hpp"
#include "splat/data/image_io.hpp"
#include "splat/data/transforms_json.hpp"
#include "splat/gaussians/ply_io.hpp"
#include "splat/raster/rasterizer.hpp"

namespace splat::cli {

namespace {

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const std::size_t mid = values.size() / 2;
  return values.size() % 2 ? values[mid] : 0.5 * (values[mid - 1] + values[mid]);
}

GaussianModel load_model(const std::filesystem::path& file) {
  if (file.extension() != ".ply")
    throw InputError(file, "unsupported model format '" + file.extension().string() +
                               "' (splat-render reads .ply)");
  return read_ply(file);
}

}  // namespace

int run_render_command(const RenderCommandOptions& options) {
  const GaussianModel model = load_model(options.model);
  TransformsOptions transforms_options;
  transforms_options.width = options.width;
  transforms_options.height = options.height;
  const std::vector<CameraFrame> frames = load_transforms(options.cameras, transforms_options);

  std::error_code ec;
  std::filesystem::create_directories(options.out, ec);
  if (ec || !std::filesystem::is_directory(options.out))
    throw InputError(options.out, "cannot create the output folder");

  RenderSettings settings;
  settings.sh_degree = options.sh_degree;
  std::copy(options.background, options.background + 3, settings.background);
  Rasterizer rasterizer;
  RenderResult result;
  std::vector<double> total_ms, project_ms, bin_sort_ms, blend_ms;

  for (const CameraFrame& frame : frames) {
    rasterizer.render(model, frame.camera, settings, result);  // also the warm-up
    const std::filesystem::path png = options.out / (frame.name + ".png");
    write_png(result.color, png, options.bits);
    for (int r = 0; r < options.bench_repeats; ++r) {
      const auto start = std::chrono::steady_clock::now();
      rasterizer.render(model, frame.camera, settings, result);
      total_ms.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count());
      const RenderTimings& t = rasterizer.last_timings();
      project_ms.push_back(t.project_ms);
      bin_sort_ms.push_back(t.bin_sort_ms);
      blend_ms.push_back(t.blend_ms);
    }
    if (options.bench_repeats == 0)
      std::printf("%s  %dx%d  %.1f ms\n", png.string().c_str(), frame.camera.width,
                  frame.camera.height, rasterizer.last_timings().total_ms());
  }
  std::printf("rendered %zu frames of %zu Gaussians into %s\n", frames.size(), model.size(),
              options.out.string().c_str());

  if (options.bench_repeats > 0) {
    const double ms = median(total_ms);
    std::printf("median ms per frame: %.3f (projection %.3f, binning+sort %.3f, blending %.3f)\n",
                ms, median(project_ms), median(bin_sort_ms), median(blend_ms));
    std::printf(
        "{\"frames\": %zu, \"width\": %d, \"height\": %d, \"ms_per_frame\": %.4f, \"fps\": %.3f, "
        "\"project_ms\": %.4f, \"bin_sort_ms\": %.4f, \"blend_ms\": %.4f, \"gaussians\": %zu, "
        "\"renders\": %zu}\n",
        frames.size(), frames.front().camera.width, frames.front().camera.height, ms,
        ms > 0 ? 1000.0 / ms : 0.0, median(project_ms), median(bin_sort_ms), median(blend_ms),
        model.size(), total_ms.size());
  }
  std::fflush(stdout);
  return 0;
}

}  // namespace splat::cli
