// Gradient conformance with the official CUDA rasterizer + PyTorch autograd
// (testdata/conformance/gradients): for view r_0 of the 50k-Gaussian lego model and
// L = Σ W·I: our unclamped image within 1e-4 of theirs at every pixel, L within 1e-4
// (relative) and ∂L/∂θ per parameter group within 1e-3 (relative L2).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "splat/data/transforms_json.hpp"
#include "splat/gaussians/ply_io.hpp"
#include "splat/raster/rasterizer.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

std::vector<float> read_f32(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::vector<float> v(std::filesystem::file_size(file) / sizeof(float));
  in.read(reinterpret_cast<char*>(v.data()), std::streamsize(v.size() * sizeof(float)));
  return v;
}

TEST(GradientConformance, MatchesOfficialGradientsForViewR0) {
  const auto dir = test::conformance_dir();
  const auto [model, frames] = test::load_conformance(400);
  const Camera camera = frames.at(0).camera;
  const std::vector<float> weights = read_f32(dir / "gradients" / "W_r_0.f32");  // [3, H, W]
  const std::vector<float> reference = read_f32(dir / "gradients" / "grad_r_0.f32");  // [N, 59]
  const std::vector<float> their_image = read_f32(dir / "gradients" / "I_r_0.f32");  // [3, H, W]
  ASSERT_EQ(weights.size(), 3u * 400 * 400);
  ASSERT_EQ(their_image.size(), 3u * 400 * 400);
  ASSERT_EQ(reference.size(), model.size() * 59);

  RenderSettings settings;  // white background, SH degree 3
  settings.alpha_clamp_gradient = AlphaClampGradient::kStraightThrough;  // the official convention
  Rasterizer rasterizer;
  RenderResult forward;
  rasterizer.render(model, camera, settings, forward);
  Image v_color(400, 400, 3);
  double loss = 0;
  for (int c = 0; c < 3; ++c)
    for (std::size_t p = 0; p < 400 * 400; ++p) {
      v_color.data[3 * p + c] = weights[c * 160000 + p];
      loss += double(weights[c * 160000 + p]) * forward.color.data[3 * p + c];
    }
  std::size_t pixels_off = 0;
  double worst = 0;
  for (int c = 0; c < 3; ++c)
    for (std::size_t p = 0; p < 400 * 400; ++p) {
      const double error = std::abs(double(forward.color.data[3 * p + c]) - their_image[c * 160000 + p]);
      worst = std::max(worst, error);
      pixels_off += error > 1e-4;
    }
  std::printf("image: largest difference %.3e, %zu values beyond 1e-4\n", worst, pixels_off);
  EXPECT_EQ(pixels_off, 0u) << "largest difference " << worst;
  constexpr double kReferenceLoss = -256.915888;  // from the gradients README (float64 sum)
  EXPECT_NEAR(loss, kReferenceLoss, 1e-4 * std::abs(kReferenceLoss));

  RasterGradients grads;
  rasterizer.backward(model, camera, settings, forward, v_color, grads);
  const GaussianModel& g = grads.params;
  // Reference columns, PLY order without normals: x y z, f_dc_0..2, f_rest_0..44
  // (channel-major), opacity, scale_0..2, rot_0..3.
  const int k = 16;
  double diff[6] = {}, norm[6] = {};
  for (std::size_t i = 0; i < model.size(); ++i) {
    const float* ref = &reference[i * 59];
    auto add = [&](int group, float ours, float theirs) {
      diff[group] += (double(ours) - theirs) * (double(ours) - theirs);
      norm[group] += double(theirs) * theirs;
    };
    for (int a = 0; a < 3; ++a) add(0, g.means[3 * i + a], ref[a]);
    for (int c = 0; c < 3; ++c) add(1, g.sh[(i * k) * 3 + c], ref[3 + c]);
    for (int c = 0; c < 3; ++c)
      for (int b = 1; b < k; ++b) add(2, g.sh[(i * k + b) * 3 + c], ref[6 + c * 15 + (b - 1)]);
    add(3, g.opacity_logits[i], ref[51]);
    for (int a = 0; a < 3; ++a) add(4, g.log_scales[3 * i + a], ref[52 + a]);
    for (int a = 0; a < 4; ++a) add(5, g.quats[4 * i + a], ref[55 + a]);
  }
  const char* names[6] = {"xyz", "f_dc", "f_rest", "opacity", "scale", "rotation"};
  for (int group = 0; group < 6; ++group) {
    const double relative = std::sqrt(diff[group] / norm[group]);
    std::printf("gradient conformance %-8s relative error %.3e\n", names[group], relative);
    EXPECT_LE(relative, 1e-3) << names[group];
  }
}

}  // namespace
}  // namespace splat
