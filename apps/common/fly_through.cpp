#include "apps/common/fly_through.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

#include "apps/common/video_writer.hpp"
#include "splat/core/atomic_file.hpp"
#include "splat/core/error.hpp"
#include "splat/data/camera_paths.hpp"
#include "splat/data/image_io.hpp"
#include "splat/data/path_framing.hpp"
#include "splat/data/transforms_json.hpp"
#include "splat/nerf/nerf_renderer.hpp"

namespace splat::cli {
namespace {

// The image size of a path with no --width/--height and no cameras.
constexpr int kDefaultPathSide = 800;

const char* path_name(CameraPathKind kind) {
  switch (kind) {
    case CameraPathKind::kOrbit: return "orbit";
    case CameraPathKind::kSpiral: return "spiral";
    case CameraPathKind::kInterpolate: return "interpolation";
    case CameraPathKind::kNone: break;
  }
  return "none";
}

// One camera's image of either kind of model.
class FrameRenderer {
 public:
  FrameRenderer(const RenderModel& model, const RenderCommandOptions& options)
      : model_(model), settings_(render_settings(options)) {}

  const Image& render(const Camera& camera) {
    if (const GaussianModel* splats = std::get_if<GaussianModel>(&model_)) {
      rasterizer_.render(*splats, camera, settings_, result_);
      return result_.color;
    }
    image_ = nerf_renderer_.render_image(std::get<NerfModel>(model_), camera, settings_.background);
    return image_;
  }

 private:
  const RenderModel& model_;
  RenderSettings settings_;
  Rasterizer rasterizer_;
  RenderResult result_;
  NerfRenderer nerf_renderer_;
  Image image_;
};

// Where the model's content is: the Gaussians' means weighted by opacity (so faint floaters
// do not count), or a NeRF's scene box. Nothing when no Gaussian is visible.
std::optional<AxisAlignedBox> content_box(const RenderModel& model) {
  if (const NerfModel* nerf = std::get_if<NerfModel>(&model)) return nerf->settings.box;
  const GaussianModel& splats = std::get<GaussianModel>(model);
  std::vector<float> opacities(splats.size());
  for (std::size_t i = 0; i < splats.size(); ++i) opacities[i] = splats.opacity(i);
  return robust_box(splats.means, opacities);
}

struct ImageSize {
  int width, height;
};

// --width/--height, else the cameras' size, else 800 x 800. A video needs even sides: a size
// we chose is rounded down to one, a size the user gave is refused.
ImageSize path_image_size(const RenderCommandOptions& options, const std::vector<CameraFrame>& views) {
  const bool video = !options.video.empty();
  if (options.width > 0) {
    if (video && (options.width % 2 != 0 || options.height % 2 != 0))
      throw ArgumentError("--width and --height must be even for --video (4:2:0 colour halves them), not " +
                          std::to_string(options.width) + "x" + std::to_string(options.height));
    return {options.width, options.height};
  }
  ImageSize size{kDefaultPathSide, kDefaultPathSide};
  if (!views.empty()) size = {views.front().camera.width, views.front().camera.height};
  if (video) size = {std::max(2, size.width / 2 * 2), std::max(2, size.height / 2 * 2)};
  return size;
}

std::vector<Camera> path_cameras(const RenderCommandOptions& options, const RenderModel& model,
                                 const std::vector<Camera>& views, ImageSize size) {
  if (options.path == CameraPathKind::kInterpolate)
    return interpolated_path(views, options.frames, size.width, size.height);
  const std::optional<AxisAlignedBox> content = content_box(model);
  if (!content && views.empty())
    throw InputError(options.model, "has no visible content to frame an orbit on (give --cameras)");
  PathFraming framing;
  if (views.empty()) {
    // Without cameras nothing says which way is up; world z is, as in the Blender scenes.
    framing = frame_box(*content, glm::vec3(0, 0, 1), float(size.width) / float(size.height));
  } else {
    framing = frame_from_cameras(views, content.value_or(AxisAlignedBox{glm::vec3(-1), glm::vec3(1)}));
  }
  if (!options.quiet)
    std::printf("%s round (%.3g, %.3g, %.3g), up (%.3g, %.3g, %.3g), %.3g away, %.0f deg above, %.0f deg field of view\n",
                path_name(options.path), framing.center.x, framing.center.y, framing.center.z, framing.up.x,
                framing.up.y, framing.up.z, framing.distance, framing.elevation * 57.29578f, framing.fov_y * 57.29578f);
  return options.path == CameraPathKind::kSpiral ? spiral_path(framing, options.frames, size.width, size.height)
                                                 : orbit_path(framing, options.frames, size.width, size.height);
}

std::string frame_file_name(int index) {
  char name[32];
  std::snprintf(name, sizeof(name), "frame_%04d.png", index);
  return name;
}

// Renders every camera, writing each image to `video` (if any) and as a PNG in --out (if
// given), with one line per frame.
void render_path(const RenderCommandOptions& options, const RenderModel& model, const std::vector<Camera>& cameras,
                 VideoWriter* video) {
  FrameRenderer renderer(model, options);
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    const auto start = std::chrono::steady_clock::now();
    const Image& image = renderer.render(cameras[i]);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (video) video->write(image);
    if (!options.out.empty()) write_png(image, options.out / frame_file_name(int(i)), options.bits);
    if (options.quiet) continue;
    std::printf("frame %zu/%zu  %dx%d  %.1f ms\n", i + 1, cameras.size(), image.width, image.height, ms);
    std::fflush(stdout);
  }
}

}  // namespace

int run_fly_through(const RenderCommandOptions& options) {
  // What a video needs is checked before anything is read or made.
  std::optional<std::filesystem::path> ffmpeg;
  if (!options.video.empty()) {
    if (const std::string problem = video_extension_problem(options.video); !problem.empty())
      throw InputError(options.video, problem);
    check_output_file_path(options.video);
    ffmpeg = find_ffmpeg();
    if (!ffmpeg) throw Error("--video encodes with ffmpeg, which is not installed (apt-get install ffmpeg)");
  }
  const RenderModel model = load_model(options.model);
  std::vector<CameraFrame> frames;
  if (!options.cameras.empty()) {
    TransformsOptions transforms_options;
    transforms_options.width = options.width;
    transforms_options.height = options.height;
    frames = load_transforms(options.cameras, transforms_options);
  }
  std::vector<Camera> views;
  for (const CameraFrame& frame : frames) views.push_back(frame.camera);
  const ImageSize size = path_image_size(options, frames);
  const std::vector<Camera> cameras = path_cameras(options, model, views, size);

  if (!options.out.empty()) create_output_folder(options.out);
  if (ffmpeg) {
    if (options.video.has_parent_path()) create_output_folder(options.video.parent_path());
    write_atomically(options.video, [&](const std::filesystem::path& temp) {
      VideoWriter video(*ffmpeg, options.video, temp, size.width, size.height, options.fps);
      render_path(options, model, cameras, &video);
      video.finish();
    });
  } else {
    render_path(options, model, cameras, nullptr);
  }
  if (options.quiet) return 0;
  std::printf("rendered %zu frames along the %s", cameras.size(), path_name(options.path));
  if (ffmpeg) std::printf(" into %s (%g fps)", options.video.string().c_str(), options.fps);
  if (!options.out.empty()) std::printf("%s PNGs in %s", ffmpeg ? " and" : " as", options.out.string().c_str());
  std::printf("\n");
  std::fflush(stdout);
  return 0;
}

}  // namespace splat::cli
