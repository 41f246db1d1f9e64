#include "apps/splat-viewer/panel_model.hpp"

#include <chrono>
#include <cmath>
#include <string>

#include "splat/core/error.hpp"
#include "splat/gaussians/model_file.hpp"
#include "splat/nerf/nerf_file.hpp"
#include "splat/nerf/nerf_renderer.hpp"

namespace splat::viewer {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

std::string thousands(std::size_t n) {
  std::string digits = std::to_string(n), out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

class SplatPanel : public PanelModel {
 public:
  explicit SplatPanel(GaussianModel model) : model_(std::move(model)) {}
  std::string description() const override {
    return thousands(model_.size()) + " Gaussians, SH degree " + std::to_string(model_.sh_degree);
  }
  std::size_t gaussian_count() const override { return model_.size(); }
  int max_sh_degree() const override { return model_.sh_degree; }
  bool progressive() const override { return false; }
  std::vector<float> framing_points() const override { return model_.means; }
  bool render(const Camera& camera, const ViewSettings& view, const std::atomic<bool>&, PanelFrame& frame) override {
    const auto start = Clock::now();
    RenderSettings settings;
    settings.sh_degree = view.sh_degree;
    settings.for_backward = false;
    for (int c = 0; c < 3; ++c) settings.background[c] = view.background[c];
    rasterizer_.render(model_, camera, settings, result_);
    frame.timings = result_.timings;
    to_rgba8(result_.color, frame.rgba);
    frame.width = camera.width;
    frame.height = camera.height;
    frame.render_ms = ms_since(start);
    return true;  // a splat frame takes milliseconds: never worth abandoning
  }

 private:
  GaussianModel model_;
  Rasterizer rasterizer_;
  RenderResult result_;
};

class NerfPanel : public PanelModel {
 public:
  explicit NerfPanel(NerfModel model) : model_(std::move(model)) {}
  std::string description() const override {
    return "NeRF, " + thousands(model_.parameter_count()) + " parameters";
  }
  std::size_t gaussian_count() const override { return 0; }
  int max_sh_degree() const override { return 0; }
  bool progressive() const override { return true; }
  std::vector<float> framing_points() const override {
    std::vector<float> corners;
    const AxisAlignedBox& box = model_.settings.box;
    for (int i = 0; i < 8; ++i)
      for (int k = 0; k < 3; ++k) corners.push_back(((i >> k) & 1) ? box.hi[k] : box.lo[k]);
    return corners;
  }
  bool render(const Camera& camera, const ViewSettings& view, const std::atomic<bool>& cancel,
              PanelFrame& frame) override {
    const auto start = Clock::now();
    if (!renderer_.render_image(model_, camera, view.background, image_, [&] { return cancel.load(); }))
      return false;
    to_rgba8(image_, frame.rgba);
    frame.width = camera.width;
    frame.height = camera.height;
    frame.timings = {};
    frame.render_ms = ms_since(start);
    return true;
  }

 private:
  NerfModel model_;
  NerfRenderer renderer_;
  Image image_;
};

}  // namespace

void to_rgba8(const Image& image, std::vector<std::uint8_t>& rgba) {
  const std::size_t pixels = std::size_t(image.width) * std::size_t(image.height);
  rgba.resize(4 * pixels);
  for (std::size_t i = 0; i < pixels; ++i) {
    for (int c = 0; c < 3; ++c) {
      float v = image.data[i * std::size_t(image.channels) + std::size_t(c)];
      v = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;  // NaN → 0, as write_png
      rgba[4 * i + std::size_t(c)] = std::uint8_t(std::lround(v * 255.0f));
    }
    rgba[4 * i + 3] = 255;
  }
}

std::unique_ptr<PanelModel> load_panel_model(const std::filesystem::path& file) {
  if (!std::filesystem::exists(file)) throw InputError(file, "no such file");
  if (is_nerf_file(file)) return std::make_unique<NerfPanel>(read_nerf(file));
  if (is_gaussian_model_extension(file.extension().string()))
    return std::make_unique<SplatPanel>(read_gaussian_model(file));
  throw InputError(file, "not a model splat-viewer reads (a Gaussian model: " + std::string(kGaussianModelExtensions) +
                             "; or a .nerf from splat-train)");
}

}  // namespace splat::viewer
