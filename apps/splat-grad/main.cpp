// splat-grad --model PLY --cameras TRANSFORMS.json --view K --width W --height H --bg COLOUR
//            --weights W.f32 --out G.f32 [--image I.f32] [--compare G_REF.f32] [--bench N]
//
// Renders view K, forms L = Σ W·I over the unclamped image I (W raw float32 [3, H, W]), and
// writes ∂L/∂θ for the raw stored parameters as raw float32 [N, 59] in PLY property order
// without the normals. Its last line is {"loss": L}. With --compare it also prints, per
// parameter group, ‖g − g_ref‖ / ‖g_ref‖ against another implementation's gradients.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "apps/common/arg_parser.hpp"
#include "apps/common/run_main.hpp"
#include "splat/core/atomic_file.hpp"
#include "splat/core/error.hpp"
#include "splat/data/transforms_json.hpp"
#include "splat/gaussians/ply_io.hpp"
#include "splat/raster/rasterizer.hpp"
#include "apps/splat-grad/gradient_layout.hpp"

namespace fs = std::filesystem;

namespace {

constexpr const char* kUsage = R"(usage: splat-grad --model PLY --cameras TRANSFORMS.json --view K
                  --width W --height H --bg COLOUR --weights W.f32 --out G.f32
                  [--image I.f32] [--compare G_REF.f32] [--bench N]

Renders view K of the transforms file, forms L = sum(W * I) over the unclamped image I
(W: raw little-endian float32, shape [3, H, W]) and writes dL/dtheta for every raw stored
parameter as raw float32 [N, 59] in PLY property order without the normals
(x y z, f_dc_0..2, f_rest_0..44, opacity, scale_0..2, rot_0..3). Prints {"loss": L} last.
  --image I.f32        also write the unclamped image, float32 [3, H, W]
  --alpha-clamp-gradient straight-through|zero
                       where alpha = min(0.99, o*G) is clamped, pass the gradient through
                       as the official CUDA rasterizer does (default), or use the exact
                       derivative, zero (what splat-train uses)
  --compare G_REF.f32  print per parameter group ||g - g_ref|| / ||g_ref||
  --bench N            after the run, time N more forward+backward pairs (warm buffers) and
                       print the medians and the median backward/forward ratio
)";

std::vector<float> read_floats(const fs::path& file, std::size_t expected_count,
                               const std::string& what) {
  std::error_code ec;
  if (!fs::exists(file, ec)) throw splat::InputError(file, "file does not exist");
  const auto size = fs::file_size(file, ec);
  if (ec) throw splat::InputError(file, "cannot read the file size");
  if (size != expected_count * sizeof(float))
    throw splat::InputError(file, what + " must hold " + std::to_string(expected_count) +
                                      " float32 values (" +
                                      std::to_string(expected_count * sizeof(float)) +
                                      " bytes), it has " + std::to_string(size) + " bytes");
  std::vector<float> values(expected_count);
  std::ifstream in(file, std::ios::binary);
  in.read(reinterpret_cast<char*>(values.data()), std::streamsize(size));
  if (!in) throw splat::InputError(file, "cannot read the file");
  for (std::size_t i = 0; i < values.size(); ++i)
    if (!std::isfinite(values[i]))
      throw splat::InputError(file, what + ": value " + std::to_string(i) + " is not finite");
  return values;
}

void write_floats(const fs::path& file, const std::vector<float>& values) {
  splat::write_stream_atomically(file, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(values.data()), std::streamsize(values.size() * sizeof(float)));
  });
}

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  return splat::cli::run_main([&] {
    splat::cli::ArgParser args(argc, argv,
                               {"model", "cameras", "view", "width", "height", "bg", "weights",
                                "out", "image", "compare", "alpha-clamp-gradient", "bench"},
                               {"help"});
    if (args.has("help")) {
      std::fputs(kUsage, stdout);
      return 0;
    }
    const fs::path model_file = args.required("model"), cameras_file = args.required("cameras");
    const fs::path weights_file = args.required("weights"), out_file = args.required("out");
    splat::check_output_file_path(out_file);
    if (auto image_file = args.value("image")) splat::check_output_file_path(*image_file);
    const std::optional<int> view_option = args.integer("view", splat::cli::kViewIndexRange);
    if (!view_option) throw splat::ArgumentError("missing required option --view");
    const int view = *view_option;
    splat::TransformsOptions size;
    const std::optional<int> width = args.integer("width", splat::cli::kImageSideRange),
                             height = args.integer("height", splat::cli::kImageSideRange);
    if (!width || !height) throw splat::ArgumentError("--width and --height are required (see --help)");
    size.width = *width;
    size.height = *height;
    const std::optional<int> bench = args.integer("bench", {1, 100000});
    const auto bg = args.colour("bg");
    if (!bg) throw splat::ArgumentError("missing required option --bg");

    const splat::GaussianModel model = splat::read_ply(model_file);
    const auto frames = splat::load_transforms(cameras_file, size);
    if (view < 0 || std::size_t(view) >= frames.size())
      throw splat::ArgumentError("--view " + std::to_string(view) + " is out of range: " +
                                 cameras_file.string() + " has " + std::to_string(frames.size()) +
                                 " frames (0.." + std::to_string(frames.size() - 1) + ")");
    const int w = size.width, h = size.height;
    const std::vector<float> weights = read_floats(weights_file, std::size_t(3) * w * h, "the weight image");
    std::vector<float> reference;
    if (auto compare = args.value("compare"))
      reference = read_floats(*compare, model.size() * splat::cli::gradient_columns(model.sh_degree),
                              "the reference gradient");

    splat::RenderSettings settings;
    for (int c = 0; c < 3; ++c) settings.background[c] = (*bg)[c];
    // Comparing with other implementations is this tool's purpose, so it follows the official
    // rasterizer's convention at the α clamp unless told otherwise.
    const std::string clamp_mode = args.value("alpha-clamp-gradient").value_or("straight-through");
    if (clamp_mode == "straight-through")
      settings.alpha_clamp_gradient = splat::AlphaClampGradient::kStraightThrough;
    else if (clamp_mode == "zero")
      settings.alpha_clamp_gradient = splat::AlphaClampGradient::kZero;
    else
      throw splat::ArgumentError("--alpha-clamp-gradient must be straight-through or zero, got '" +
                                 clamp_mode + "'");
    splat::Rasterizer rasterizer;
    splat::RenderResult result;
    const splat::Camera& camera = frames[std::size_t(view)].camera;
    auto start = std::chrono::steady_clock::now();
    rasterizer.render(model, camera, settings, result);
    const double forward_ms = ms_since(start);

    // L = Σ W·I: ∂L/∂I = W, moved from planar [3, H, W] to the image's [H, W, 3].
    splat::Image v_color(w, h, 3);
    double loss = 0;
    for (int c = 0; c < 3; ++c)
      for (std::size_t p = 0; p < std::size_t(w) * h; ++p) {
        const float weight = weights[std::size_t(c) * w * h + p];
        v_color.data[3 * p + c] = weight;
        loss += double(weight) * double(result.color.data[3 * p + c]);
      }
    splat::RasterGradients grads;
    start = std::chrono::steady_clock::now();
    rasterizer.backward(model, camera, settings, result, v_color, grads);
    const double backward_ms = ms_since(start);

    const std::vector<float> table = splat::cli::gradient_table(grads.params);
    write_floats(out_file, table);
    if (auto image_file = args.value("image")) {
      std::vector<float> planar(std::size_t(3) * w * h);
      for (int c = 0; c < 3; ++c)
        for (std::size_t p = 0; p < std::size_t(w) * h; ++p)
          planar[std::size_t(c) * w * h + p] = result.color.data[3 * p + c];
      write_floats(*image_file, planar);
    }
    std::printf("view %d (%s), %zu Gaussians, %dx%d: forward %.2f ms, backward %.2f ms (x%.2f)\n",
                view, frames[std::size_t(view)].name.c_str(), model.size(), w, h, forward_ms,
                backward_ms, backward_ms / forward_ms);
    if (bench) {
      // The first pair above allocated the buffers; these reuse them, as training does.
      std::vector<double> forward_times, backward_times, ratios;
      for (int i = 0; i < *bench; ++i) {
        start = std::chrono::steady_clock::now();
        rasterizer.render(model, camera, settings, result);
        forward_times.push_back(ms_since(start));
        start = std::chrono::steady_clock::now();
        rasterizer.backward(model, camera, settings, result, v_color, grads);
        backward_times.push_back(ms_since(start));
        ratios.push_back(backward_times.back() / forward_times.back());
      }
      std::printf("bench %d pairs: forward median %.2f ms, backward median %.2f ms, "
                  "backward/forward median %.2f\n",
                  *bench, median(forward_times), median(backward_times), median(ratios));
    }
    if (!reference.empty())
      for (const auto& group : splat::cli::compare_gradient_groups(table, reference, model.sh_degree))
        std::printf("group %-8s |g_ref| %.6g  relative error %.3e\n", group.name.c_str(),
                    group.reference_norm, group.relative_error);
    std::printf("{\"loss\": %.9g}\n", loss);
    return 0;
  });
}
