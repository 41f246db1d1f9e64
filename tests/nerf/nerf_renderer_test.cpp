// The NeRF renderer end to end: its parameter gradients (coarse network through the coarse
// colour, fine network through the fine colour) against central finite differences of the
// rendered colours, and determinism for a seed.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "splat/core/error.hpp"
#include "splat/nerf/nerf_file.hpp"
#include "splat/nerf/nerf_renderer.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

NerfSettings tiny_settings() {
  NerfSettings s;
  s.coarse = frequency_mlp_config(2, 1, 2, 8, -1, 6);
  s.fine = frequency_mlp_config(2, 1, 2, 8, -1, 6);
  s.coarse_samples = 8;
  s.fine_samples = 8;
  // The unjittered renders below then place the samples training does (8 per ray), the
  // case whose gradients train the networks.
  s.render_sample_multiplier = 1;
  s.box = {glm::vec3(-1.0f), glm::vec3(1.0f)};
  return s;
}

std::vector<Ray> tiny_rays() {
  const Camera camera = test::looking_at_origin(8, 8, 3.0f, 0.9f);
  std::vector<Ray> rays;
  for (int y = 1; y < 8; y += 2)
    for (int x = 0; x < 8; x += 3) rays.push_back(camera_ray(camera, float(x), float(y)));
  return rays;
}

// ⟨weights, colour⟩ for the coarse or fine colour of a deterministic (unjittered) render.
double weighted_colour(const NerfModel& model, const std::vector<Ray>& rays, bool fine,
                       const std::vector<float>& weights) {
  NerfRenderer renderer;
  NerfForwardContext forward;
  std::mt19937 rng(0);
  const float bg[3] = {1, 1, 1};
  renderer.forward(model, rays, bg, false, rng, forward);
  const auto& colour = fine ? forward.fine_color() : forward.coarse_color();
  double sum = 0;
  for (std::size_t i = 0; i < colour.size(); ++i) sum += double(weights[i]) * colour[i];
  return sum;
}

TEST(NerfRenderer, ParameterGradientsMatchFiniteDifferences) {
  NerfModel model(tiny_settings(), 3);
  // Biases that give the field some structure (zero-initialised biases would leave σ flat).
  std::mt19937 init(5);
  std::normal_distribution<float> normal(0.0f, 0.5f);
  for (float& p : model.coarse.parameters()) p += 0.3f * normal(init);
  for (float& p : model.fine.parameters()) p += 0.3f * normal(init);
  const std::vector<Ray> rays = tiny_rays();
  std::vector<float> w(3 * rays.size());
  for (float& v : w) v = normal(init);

  NerfRenderer renderer;
  NerfForwardContext forward;
  std::mt19937 rng(0);
  const float bg[3] = {1, 1, 1};
  renderer.forward(model, rays, bg, false, rng, forward);
  std::vector<float> g_coarse(model.coarse.parameter_count(), 0.0f), g_fine(model.fine.parameter_count(), 0.0f);
  renderer.backward(model, forward, w, w, g_coarse, g_fine);

  // Float renders: a step of 1e-2 keeps rounding well below the change being measured.
  const double h = 1e-2;
  int checked = 0;
  for (bool fine : {false, true}) {
    NerfMlp& mlp = fine ? model.fine : model.coarse;
    const std::vector<float>& g = fine ? g_fine : g_coarse;
    for (std::size_t i = 0; i < mlp.parameter_count(); i += 7) {
      const float saved = mlp.parameters()[i];
      mlp.parameters()[i] = float(saved + h);
      const double plus = weighted_colour(model, rays, fine, w);
      mlp.parameters()[i] = float(saved - h);
      const double minus = weighted_colour(model, rays, fine, w);
      mlp.parameters()[i] = saved;
      const double numeric = (plus - minus) / (2 * h);
      EXPECT_NEAR(g[i], numeric, 2e-3 + 2e-2 * std::abs(numeric)) << (fine ? "fine " : "coarse ") << i;
      ++checked;
    }
  }
  EXPECT_GT(checked, 50);
  double norm = 0;
  for (float v : g_fine) norm += double(v) * v;
  EXPECT_GT(norm, 1e-6);  // the check is not vacuous
}

TEST(NerfRenderer, EvaluationRendersPlaceTheMultiplierTimesTheCoarseSamples) {
  NerfSettings settings = tiny_settings();
  settings.render_sample_multiplier = 3;
  const NerfModel model(settings, 4);  // every grid cell occupied: no sample dropped
  const std::vector<Ray> rays = tiny_rays();
  const float bg[3] = {1, 1, 1};
  NerfRenderer renderer;
  NerfForwardContext forward;
  std::mt19937 rng(1);
  renderer.forward(model, rays, bg, /*jitter=*/true, rng, forward);
  const std::size_t training = forward.coarse_sample_count();
  renderer.forward(model, rays, bg, /*jitter=*/false, rng, forward);
  EXPECT_GT(training, 0u);
  EXPECT_EQ(forward.coarse_sample_count(), 3 * training);
  // Capped at the samples a ray may have.
  settings.coarse_samples = 600;
  EXPECT_EQ(settings.coarse_samples_for(/*evaluation=*/true), kMaxNerfSamplesPerRay);
  EXPECT_EQ(settings.coarse_samples_for(/*evaluation=*/false), 600);
}

TEST(NerfRenderer, FilesWithoutTheMultiplierRenderAsTheyWereTrained) {
  nlohmann::json old = nerf_settings_json(NerfSettings{});
  old.erase("render_sample_multiplier");
  EXPECT_EQ(nerf_settings_from_json(old).render_sample_multiplier, 1);
  EXPECT_EQ(nerf_settings_from_json(nerf_settings_json(NerfSettings{})).render_sample_multiplier, 2);
  old["render_sample_multiplier"] = 17;
  EXPECT_THROW(nerf_settings_from_json(old), ArgumentError);
}

TEST(NerfRenderer, SameSeedSameColours) {
  const NerfModel model(tiny_settings(), 4);
  const std::vector<Ray> rays = tiny_rays();
  const float bg[3] = {0, 0, 0};
  NerfRenderer renderer;
  NerfForwardContext a, b;
  std::mt19937 rng_a(9), rng_b(9);
  renderer.forward(model, rays, bg, true, rng_a, a);
  renderer.forward(model, rays, bg, true, rng_b, b);
  EXPECT_EQ(a.fine_color(), b.fine_color());
  EXPECT_EQ(a.coarse_color(), b.coarse_color());
}

}  // namespace
}  // namespace splat
