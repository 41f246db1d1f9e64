#include "apps/common/render_command.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "apps/common/fly_through.hpp"
#include "splat/core/error.hpp"
#include "splat/data/image_io.hpp"
#include "splat/data/transforms_json.hpp"
#include "splat/gaussians/model_file.hpp"
#include "splat/nerf/nerf_file.hpp"
#include "splat/nerf/nerf_renderer.hpp"
#include "splat/raster/rasterizer.hpp"

namespace splat::cli {

namespace {

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const std::size_t mid = values.size() / 2;
  return values.size() % 2 ? values[mid] : 0.5 * (values[mid - 1] + values[mid]);
}

void print_bench_json(std::size_t frames, const Camera& camera, const std::vector<double>& total_ms,
                      const char* extra) {
  const double ms = median(total_ms);
  std::printf("{\"frames\": %zu, \"width\": %d, \"height\": %d, \"ms_per_frame\": %.4f, \"fps\": %.3f%s, "
              "\"renders\": %zu}\n",
              frames, camera.width, camera.height, ms, ms > 0 ? 1000.0 / ms : 0.0, extra, total_ms.size());
}

// A NeRF renders ray by ray through its networks (no rasterizer, no SH degree).
int render_nerf(const RenderCommandOptions& options, const NerfModel& model,
                const std::vector<CameraFrame>& frames) {
  NerfRenderer renderer;
  std::vector<double> total_ms;
  for (const CameraFrame& frame : frames) {
    auto start = std::chrono::steady_clock::now();
    Image image = renderer.render_image(model, frame.camera, options.background);
    double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    for (float& v : image.data) v = std::clamp(v, 0.0f, 1.0f);
    const std::filesystem::path png = options.out / (frame.name + ".png");
    write_png(image, png, options.bits);
    for (int r = 0; r < options.bench_repeats; ++r) {
      start = std::chrono::steady_clock::now();
      renderer.render_image(model, frame.camera, options.background);
      total_ms.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    }
    if (options.bench_repeats == 0)
      std::printf("%s  %dx%d  %.1f ms\n", png.string().c_str(), frame.camera.width, frame.camera.height, ms);
  }
  std::printf("rendered %zu frames of a NeRF (%zu parameters) into %s\n", frames.size(),
              model.parameter_count(), options.out.string().c_str());
  if (options.bench_repeats > 0) {
    std::printf("median ms per frame: %.3f\n", median(total_ms));
    char extra[64];
    std::snprintf(extra, sizeof(extra), ", \"parameters\": %zu", model.parameter_count());
    print_bench_json(frames.size(), frames.front().camera, total_ms, extra);
  }
  std::fflush(stdout);
  return 0;
}

}  // namespace

RenderModel load_model(const std::filesystem::path& file) {
  const std::string formats = std::string(kGaussianModelExtensions) + ", .nerf and .ngp";
  if (std::filesystem::is_directory(file))
    throw InputError(file, "is a folder, not a model file (splat-render reads " + formats + ")");
  const std::string extension = file.extension().string();
  if (is_gaussian_model_extension(extension)) return read_gaussian_model(file);
  if (extension != ".nerf" && extension != ".ngp") throw InputError(file, "unsupported model format '" + extension + "' (splat-render reads " + formats + ")");
  if (!std::filesystem::exists(file)) throw InputError(file, "file does not exist");
  return read_nerf(file);
}

void create_output_folder(const std::filesystem::path& folder) {
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec || !std::filesystem::is_directory(folder)) throw InputError(folder, "cannot create the output folder");
}

RenderSettings render_settings(const RenderCommandOptions& options) {
  RenderSettings settings;
  settings.sh_degree = options.sh_degree;
  settings.for_backward = false;
  std::copy(options.background, options.background + 3, settings.background);
  return settings;
}

int run_render_command(const RenderCommandOptions& options) {
  if (options.path != CameraPathKind::kNone) return run_fly_through(options);
  // The model first: a missing or malformed model is the likelier mistake, and is named.
  const RenderModel loaded = load_model(options.model);
  TransformsOptions transforms_options;
  transforms_options.width = options.width;
  transforms_options.height = options.height;
  const std::vector<CameraFrame> frames = load_transforms(options.cameras, transforms_options);

  create_output_folder(options.out);
  if (const NerfModel* nerf = std::get_if<NerfModel>(&loaded)) return render_nerf(options, *nerf, frames);
  const GaussianModel& model = std::get<GaussianModel>(loaded);

  const RenderSettings settings = render_settings(options);
  Rasterizer rasterizer;
  RenderResult result;
  std::vector<double> total_ms, project_ms, bin_sort_ms, blend_ms;
  BlendWorkCounts work;  // summed over the frames, counted once per frame

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
      const RenderTimings& t = result.timings;
      project_ms.push_back(t.project_ms);
      bin_sort_ms.push_back(t.bin_sort_ms);
      blend_ms.push_back(t.blend_ms);
    }
    if (options.bench_repeats > 0) work += count_blend_work(result);
    if (options.bench_repeats == 0)
      std::printf("%s  %dx%d  %.1f ms\n", png.string().c_str(), frame.camera.width,
                  frame.camera.height, result.timings.total_ms());
  }
  std::printf("rendered %zu frames of %zu Gaussians into %s\n", frames.size(), model.size(),
              options.out.string().c_str());

  if (options.bench_repeats > 0) {
    const double ms = median(total_ms);
    std::printf("median ms per frame: %.3f (projection %.3f, binning+sort %.3f, blending %.3f)\n",
                ms, median(project_ms), median(bin_sort_ms), median(blend_ms));
    // Work per frame (means over the frames), and the blend's pixel evaluations per second
    // per core: over its median time and the threads it ran on.
    const double n = double(frames.size());
    const std::size_t threads =
        tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
    const double blend_s = median(blend_ms) * 1e-3;
    const double evals_per_core_second =
        blend_s > 0 ? double(work.pixel_evaluations) / n / blend_s / double(threads) : 0.0;
    std::printf("per frame: %.0f Gaussian-tile pairs listed, %.0f visited, %.0f with a pixel at "
                "alpha >= 1/255; %.0f pixel evaluations (%.1f %% passing), %.3g per second per "
                "core (%zu threads)\n",
                double(work.list_entries) / n, double(work.visited_entries) / n,
                double(work.reaching_entries) / n, double(work.pixel_evaluations) / n,
                work.pixel_evaluations > 0
                    ? 100.0 * double(work.passing_evaluations) / double(work.pixel_evaluations)
                    : 0.0,
                evals_per_core_second, threads);
    std::printf(
        "{\"frames\": %zu, \"width\": %d, \"height\": %d, \"ms_per_frame\": %.4f, \"fps\": %.3f, "
        "\"project_ms\": %.4f, \"bin_sort_ms\": %.4f, \"blend_ms\": %.4f, \"gaussians\": %zu, "
        "\"pairs_listed\": %.0f, \"pairs_in_box\": %.0f, \"pairs_reaching\": %.0f, "
        "\"pairs_visited\": %.0f, \"pixel_evaluations\": %.0f, \"passing_evaluations\": %.0f, "
        "\"evaluations_per_core_second\": %.4g, \"threads\": %zu, \"renders\": %zu}\n",
        frames.size(), frames.front().camera.width, frames.front().camera.height, ms,
        ms > 0 ? 1000.0 / ms : 0.0, median(project_ms), median(bin_sort_ms), median(blend_ms),
        model.size(), double(work.list_entries) / n, double(work.box_entries) / n,
        double(work.reaching_entries) / n, double(work.visited_entries) / n,
        double(work.pixel_evaluations) / n, double(work.passing_evaluations) / n,
        evals_per_core_second, threads, total_ms.size());
  }
  std::fflush(stdout);
  return 0;
}

}  // namespace splat::cli
