// Properties of the backward pass: thread-count invariance, the α clamp, culled Gaussians,
// and agreement with the naive reference on which Gaussians receive gradient.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <tbb/global_control.h>

#include "splat/core/error.hpp"

#include "splat/raster/rasterizer.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

struct BackwardRun {
  RenderResult forward;
  RasterGradients grads;
};

BackwardRun run(const GaussianModel& model, const Camera& camera, const RenderSettings& settings,
                unsigned weight_seed) {
  BackwardRun r;
  Rasterizer rasterizer;
  rasterizer.render(model, camera, settings, r.forward);
  r.grads.with_camera_pose = true;
  Image v_color(camera.width, camera.height, 3);
  std::mt19937 rng(weight_seed);
  std::normal_distribution<float> normal;
  for (float& v : v_color.data) v = normal(rng);
  rasterizer.backward(model, camera, settings, r.forward, v_color, r.grads);
  return r;
}

TEST(Backward, GradientsAreBitIdenticalForAnyThreadCount) {
  const GaussianModel model = test::random_model(3000, 3, 21, 1.5f, 0.005f, 0.3f);
  const Camera camera = test::looking_at_origin(150, 110, 3.0f, 0.9f);
  BackwardRun runs[3];
  const int threads[3] = {1, 2, 5};
  for (int i = 0; i < 3; ++i) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads[i]);
    runs[i] = run(model, camera, RenderSettings{}, 4);
  }
  for (int i = 1; i < 3; ++i) {
    EXPECT_EQ(runs[0].grads.params.means, runs[i].grads.params.means);
    EXPECT_EQ(runs[0].grads.params.log_scales, runs[i].grads.params.log_scales);
    EXPECT_EQ(runs[0].grads.params.quats, runs[i].grads.params.quats);
    EXPECT_EQ(runs[0].grads.params.opacity_logits, runs[i].grads.params.opacity_logits);
    EXPECT_EQ(runs[0].grads.params.sh, runs[i].grads.params.sh);
    EXPECT_EQ(runs[0].grads.viewspace_grad_norm, runs[i].grads.viewspace_grad_norm);
    EXPECT_EQ(runs[0].grads.camera_pose.rotation, runs[i].grads.camera_pose.rotation);
    EXPECT_EQ(runs[0].grads.camera_pose.translation, runs[i].grads.camera_pose.translation);
  }
  EXPECT_NE(runs[0].grads.camera_pose.translation, glm::vec3(0.0f));  // the scene moves it
}

TEST(Backward, CulledGaussiansGetZeroGradient) {
  GaussianModel model = test::random_model(50, 2, 22, 0.5f);
  model.means[3 * 7 + 2] = -10.0f;  // behind the camera (camera at z = -3)
  model.means[3 * 8 + 0] = 40.0f;   // far outside the view
  const BackwardRun r = run(model, test::looking_at_origin(64, 64, 3.0f), RenderSettings{}, 5);
  for (int i : {7, 8}) {
    for (int a = 0; a < 3; ++a) EXPECT_EQ(r.grads.params.means[3 * i + a], 0.0f);
    EXPECT_EQ(r.grads.params.opacity_logits[i], 0.0f);
    EXPECT_EQ(r.grads.viewspace_grad_norm[i], 0.0f);
  }
  int with_gradient = 0;
  for (std::size_t i = 0; i < model.size(); ++i) with_gradient += r.grads.params.opacity_logits[i] != 0.0f;
  EXPECT_GT(with_gradient, 30);
}

// One opaque Gaussian in front of the camera: at its centre o·G > 0.99, so α is clamped.
GaussianModel opaque_gaussian(float opacity) {
  GaussianModel m;
  m.sh_degree = 0;
  m.resize(1);
  m.quats[0] = 1;
  for (int a = 0; a < 3; ++a) m.log_scales[a] = 0.0f;  // scale 1: ~150 px wide in the view below
  m.opacity_logits[0] = std::log(opacity / (1 - opacity));
  m.sh[0] = 0.5f;
  return m;
}

TEST(Backward, ClampedAlphaHasZeroOpacityGradientByDefault) {
  const Camera camera = test::looking_at_origin(9, 9, 3.0f, 0.02f);  // all pixels near the centre
  RenderSettings settings;
  const BackwardRun exact = run(opaque_gaussian(0.999f), camera, settings, 6);
  for (float a : exact.forward.alpha) ASSERT_FLOAT_EQ(a, 0.99f);  // clamped everywhere
  EXPECT_EQ(exact.grads.params.opacity_logits[0], 0.0f);
  // The reference rasterizer's convention passes it through instead.
  settings.alpha_clamp_gradient = AlphaClampGradient::kStraightThrough;
  const BackwardRun straight = run(opaque_gaussian(0.999f), camera, settings, 6);
  EXPECT_NE(straight.grads.params.opacity_logits[0], 0.0f);
  // Colour still gets its gradient either way.
  EXPECT_EQ(exact.grads.params.sh[0], straight.grads.params.sh[0]);
  EXPECT_NE(exact.grads.params.sh[0], 0.0f);
}

TEST(Backward, RejectsMismatchedCotangent) {
  const GaussianModel model = test::random_model(10, 0, 23);
  const Camera camera = test::looking_at_origin(16, 16);
  Rasterizer rasterizer;
  RenderResult forward;
  rasterizer.render(model, camera, RenderSettings{}, forward);
  RasterGradients grads;
  EXPECT_THROW(rasterizer.backward(model, camera, RenderSettings{}, forward, Image(8, 16, 3), grads),
               ArgumentError);
}

TEST(Backward, TakesItsFrameFromTheForwardResultItIsGiven) {
  // Two forward results from one rasterizer: each backward reads its own result's frame, not
  // whatever was rendered last, and a result of another model is refused.
  const GaussianModel model = test::random_model(40, 1, 24);
  const GaussianModel other = test::random_model(41, 1, 25);
  const Camera camera = test::looking_at_origin(24, 20);
  Rasterizer rasterizer;
  RenderResult first, second;
  rasterizer.render(model, camera, RenderSettings{}, first);
  Image v_color(24, 20, 3);
  std::mt19937 rng(26);
  std::normal_distribution<float> normal;
  for (float& v : v_color.data) v = normal(rng);
  RasterGradients expected, got;
  rasterizer.backward(model, camera, RenderSettings{}, first, v_color, expected);
  rasterizer.render(other, camera, RenderSettings{}, second);
  rasterizer.backward(model, camera, RenderSettings{}, first, v_color, got);
  EXPECT_EQ(got.params.means, expected.params.means);
  EXPECT_EQ(got.params.opacity_logits, expected.params.opacity_logits);
  EXPECT_THROW(rasterizer.backward(model, camera, RenderSettings{}, second, v_color, got),
               ArgumentError);
}

TEST(Backward, RefusesAFrameRenderedOnlyToBeLookedAt) {
  // A render without the blend's record (for_backward off) has the same image, and a backward
  // pass on it is refused rather than walking a record that is not there.
  const GaussianModel model = test::random_model(60, 1, 27);
  const Camera camera = test::looking_at_origin(40, 24);
  Rasterizer rasterizer;
  RenderResult recorded, looked_at;
  rasterizer.render(model, camera, RenderSettings{}, recorded);
  RenderSettings view_only;
  view_only.for_backward = false;
  rasterizer.render(model, camera, view_only, looked_at);
  EXPECT_EQ(looked_at.color.data, recorded.color.data);
  EXPECT_EQ(looked_at.alpha, recorded.alpha);
  EXPECT_EQ(looked_at.depth, recorded.depth);
  // Nor is the backward's per-pixel state written.
  EXPECT_TRUE(looked_at.contributor_count.empty());
  EXPECT_TRUE(looked_at.final_transmittance.empty());
  EXPECT_FALSE(recorded.contributor_count.empty());
  EXPECT_FALSE(recorded.frame.entry_chunks.empty());
  Image v_color(40, 24, 3);
  for (float& v : v_color.data) v = 1.0f;
  RasterGradients grads;
  EXPECT_THROW(rasterizer.backward(model, camera, RenderSettings{}, looked_at, v_color, grads),
               ArgumentError);
}

}  // namespace
}  // namespace splat
