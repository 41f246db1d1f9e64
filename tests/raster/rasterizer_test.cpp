// The tiled rasterizer against the naive reference, and its invariances.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <tbb/global_control.h>

#include "splat/raster/rasterizer.hpp"
#include "tests/raster/reference_rasterizer.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

struct Scene {
  GaussianModel model;
  Camera camera;
};

// Random Gaussians around the origin, some crossing the image border, some behind the
// camera, some very flat or very small; image sizes that are not multiples of the tile.
Scene random_scene(unsigned seed, int width, int height, int count) {
  Scene s;
  s.model = test::random_model(count, 3, seed, 1.6f, 0.005f, 0.4f);
  // Make a few nearly degenerate: one axis a thousand times thinner.
  for (int i = 0; i < count; i += 7) s.model.log_scales[3 * i + 2] = std::log(1e-4f);
  s.camera = test::looking_at_origin(width, height, 3.0f, 0.9f);
  return s;
}

void expect_matches_reference(const Scene& scene, const RenderSettings& settings) {
  Rasterizer rasterizer;
  RenderResult tiled, reference;
  rasterizer.render(scene.model, scene.camera, settings, tiled);
  std::vector<std::uint32_t> reference_last;
  test::render_reference(scene.model, scene.camera, settings, reference, &reference_last);

  const int w = scene.camera.width;
  const TileGrid grid = tiled.frame.grid;
  const TileBins& bins = tiled.frame.bins;
  int blended_pixels = 0;
  for (std::size_t p = 0; p < tiled.alpha.size(); ++p) {
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(tiled.color.data[3 * p + c], reference.color.data[3 * p + c], 2e-5) << p;
    ASSERT_NEAR(tiled.alpha[p], reference.alpha[p], 2e-5) << p;
    ASSERT_NEAR(tiled.depth[p], reference.depth[p], 1e-4) << p;
    ASSERT_NEAR(tiled.final_transmittance[p], reference.final_transmittance[p], 2e-5) << p;
    // The last blended Gaussian is the same one.
    const int x = int(p % w), y = int(p / w);
    const std::size_t tile = std::size_t(y / 16) * grid.tiles_x + x / 16;
    const std::uint32_t count = tiled.contributor_count[p];
    const std::uint32_t last_id =
        count == 0 ? test::kNoGaussian : bins.gaussian_ids[bins.tile_start[tile] + count - 1];
    ASSERT_EQ(last_id, reference_last[p]) << "pixel " << x << "," << y;
    blended_pixels += count > 0;
  }
  // The scene must actually draw something for the comparison to mean anything.
  EXPECT_GT(blended_pixels, int(tiled.alpha.size() / 4));
}

TEST(Rasterizer, MatchesNaiveReferenceOnRandomScenes) {
  RenderSettings settings;
  settings.background[0] = 0.2f;
  settings.background[1] = 0.5f;
  settings.background[2] = 0.9f;
  expect_matches_reference(random_scene(1, 77, 53, 300), settings);
  expect_matches_reference(random_scene(2, 64, 64, 600), settings);
  settings.sh_degree = 1;
  expect_matches_reference(random_scene(3, 50, 90, 400), settings);
}

TEST(Rasterizer, MatchesReferenceWhenPixelsSaturate) {
  // Many opaque Gaussians: most pixels stop early on T < 1e-4.
  Scene scene = random_scene(4, 48, 40, 500);
  for (float& o : scene.model.opacity_logits) o = 6.0f;
  expect_matches_reference(scene, RenderSettings{});
}

TEST(Rasterizer, EmptyModelGivesTheBackground) {
  GaussianModel empty;
  empty.sh_degree = 3;
  Rasterizer rasterizer;
  RenderResult result;
  RenderSettings settings;
  settings.background[1] = 0.25f;
  rasterizer.render(empty, test::looking_at_origin(33, 17), settings, result);
  for (std::size_t p = 0; p < result.alpha.size(); ++p) {
    EXPECT_EQ(result.color.data[3 * p + 1], 0.25f);
    EXPECT_EQ(result.alpha[p], 0.0f);
    EXPECT_EQ(result.contributor_count[p], 0u);
  }
}

TEST(Rasterizer, GaussianOutsideTheViewLeavesTheImageUnchanged) {
  Scene scene = random_scene(5, 64, 48, 100);
  Rasterizer rasterizer;
  RenderResult before, after;
  rasterizer.render(scene.model, scene.camera, RenderSettings{}, before);
  GaussianModel more = scene.model;
  more.resize(more.size() + 2);
  const std::size_t a = more.size() - 2, b = more.size() - 1;
  more.means[3 * a + 0] = 50.0f;   // far to the side
  more.means[3 * b + 2] = -10.0f;  // behind the camera (camera at z = -3)
  more.quats[4 * a] = more.quats[4 * b] = 1.0f;
  rasterizer.render(more, scene.camera, RenderSettings{}, after);
  EXPECT_EQ(0, std::memcmp(before.color.data.data(), after.color.data.data(),
                           before.color.data.size() * sizeof(float)));
}

TEST(Rasterizer, ImageIsBitIdenticalForAnyThreadCount) {
  Scene scene = random_scene(6, 160, 120, 3000);
  RenderResult results[3];
  const int threads[3] = {1, 2, 5};
  for (int i = 0; i < 3; ++i) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads[i]);
    Rasterizer rasterizer;
    rasterizer.render(scene.model, scene.camera, RenderSettings{}, results[i]);
  }
  for (int i = 1; i < 3; ++i) {
    EXPECT_EQ(results[0].color.data, results[i].color.data);
    EXPECT_EQ(results[0].depth, results[i].depth);
    EXPECT_EQ(results[0].final_transmittance, results[i].final_transmittance);
    EXPECT_EQ(results[0].contributor_count, results[i].contributor_count);
  }
}

TEST(Rasterizer, SingleGaussianHasTheExpectedPeak) {
  // One isotropic Gaussian on the axis, opacity 0.5, DC colour giving exactly 0.75 red.
  GaussianModel m;
  m.sh_degree = 0;
  m.resize(1);
  m.quats[0] = 1;
  for (int a = 0; a < 3; ++a) m.log_scales[a] = std::log(0.05f);
  m.opacity_logits[0] = 0.0f;  // sigmoid = 0.5
  m.sh[0] = float(0.25 / 0.28209479177387814);
  Camera cam = test::looking_at_origin(32, 32, 4.0f);
  cam.cx = cam.cy = 16.5f;  // mean lands exactly on pixel (16, 16)'s centre
  RenderSettings settings;
  settings.background[0] = settings.background[1] = settings.background[2] = 0.0f;
  Rasterizer r;
  RenderResult out;
  r.render(m, cam, settings, out);
  const std::size_t p = 16 * 32 + 16;
  EXPECT_NEAR(out.alpha[p], 0.5f, 1e-6);
  EXPECT_NEAR(out.color.data[3 * p], 0.5f * 0.75f, 1e-6);
  EXPECT_NEAR(out.color.data[3 * p + 1], 0.5f * 0.5f, 1e-6);
  EXPECT_NEAR(out.depth[p], 0.5f * 4.0f, 1e-5);
  EXPECT_EQ(out.contributor_count[p], 1u);
  EXPECT_LT(out.alpha[0], 1e-6);  // the corner is far outside
}

}  // namespace
}  // namespace splat
