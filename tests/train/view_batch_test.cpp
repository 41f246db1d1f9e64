// Batches of views: events fall in the step whose views hold them, the batch's gradient is
// one fixed pairwise sum that blocks of the batch reproduce bit for bit (what makes a model
// independent of how many ranks share the views), and a trainer's batch step takes the mean
// of its views' gradients.
#include "splat/train/view_batch.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "splat/data/orbit_cameras.hpp"
#include "splat/optim/photometric_loss.hpp"
#include "splat/optim/step_events.hpp"
#include "splat/raster/rasterizer.hpp"
#include "splat/train/splat_trainer.hpp"

namespace splat {
namespace {

TEST(StepEvents, AnEventFallsInTheStepWhoseViewsHoldIt) {
  for (int last = 1; last <= 40; ++last)  // one view per step: the plain tests
    for (int interval : {1, 3, 7}) {
      EXPECT_EQ(step_reaches_multiple(last, 1, interval), last % interval == 0);
      EXPECT_EQ(step_reaches(last, 1, interval), last == interval);
    }
  // Steps of 4 views: (0, 4], (4, 8], ... Every 6 views: at 6, 12 → steps ending 8 and 12.
  EXPECT_FALSE(step_reaches_multiple(4, 4, 6));
  EXPECT_TRUE(step_reaches_multiple(8, 4, 6));
  EXPECT_TRUE(step_reaches_multiple(12, 4, 6));
  EXPECT_FALSE(step_reaches_multiple(16, 4, 6));
  EXPECT_TRUE(step_reaches(8, 4, 5));
  EXPECT_FALSE(step_reaches(8, 4, 4));
  EXPECT_FALSE(step_reaches_multiple(8, 4, 0));  // no interval, no event
}

GaussianModel random_gradient(std::mt19937& rng, std::size_t n) {
  GaussianModel g;
  g.sh_degree = 1;
  g.resize(n);
  // Magnitudes over many octaves, so that the order of a sum changes its rounding.
  std::uniform_real_distribution<float> mantissa(-1.0f, 1.0f);
  std::uniform_int_distribution<int> exponent(-20, 20);
  for (std::vector<float>* a : {&g.means, &g.log_scales, &g.quats, &g.opacity_logits, &g.sh})
    for (float& v : *a) v = std::ldexp(mantissa(rng), exponent(rng));
  return g;
}

std::vector<float> flat(const GaussianModel& g) {
  std::vector<float> out;
  for (const std::vector<float>* a : {&g.means, &g.log_scales, &g.quats, &g.opacity_logits, &g.sh})
    out.insert(out.end(), a->begin(), a->end());
  return out;
}

TEST(PairwiseGradientSum, BlocksOfAPowerOfTwoViewsReproduceTheWholeBatchBitForBit) {
  std::mt19937 rng(3);
  for (const int batch : {2, 4, 6, 8, 12}) {
    std::vector<GaussianModel> views;
    for (int v = 0; v < batch; ++v) views.push_back(random_gradient(rng, 50));
    PairwiseGradientSum whole;
    for (const GaussianModel& g : views) whole.add(g);
    const std::vector<float> expected = flat(whole.total());

    // Summed in view order from the left instead, the floats differ (from 3 views on, where
    // the two orders part): the order is a real choice, and the check below can fail.
    GaussianModel left = views[0];
    for (int v = 1; v < batch; ++v) left.add(views[std::size_t(v)]);
    if (batch > 2) EXPECT_NE(flat(left), expected) << "batch " << batch;

    for (const int block : {1, 2, 4}) {  // the views each of batch / block ranks would take
      if (batch % block != 0) continue;
      PairwiseGradientSum across_blocks;
      for (int first = 0; first < batch; first += block) {
        PairwiseGradientSum one_block;
        for (int v = first; v < first + block; ++v) one_block.add(views[std::size_t(v)]);
        across_blocks.add(one_block.total());
      }
      EXPECT_EQ(flat(across_blocks.total()), expected) << "batch " << batch << ", blocks of " << block;
    }
  }
  // Reused after clear(), the buffers give the same sum again.
  PairwiseGradientSum sum;
  const GaussianModel a = random_gradient(rng, 10), b = random_gradient(rng, 10);
  sum.add(a);
  sum.add(b);
  const std::vector<float> first = flat(sum.total());
  sum.clear();
  sum.add(a);
  sum.add(b);
  EXPECT_EQ(flat(sum.total()), first);
  sum.clear();
  EXPECT_THROW(sum.total(), ArgumentError);
}

// Two views of a sky-blue orbit: a batch of both takes them in either order, and two floats
// add the same either way, so the step's gradient is (g₀ + g₁)/2 exactly.
TEST(SplatTrainer, ABatchStepTakesTheMeanOfItsViewsGradients) {
  OrbitRig rig;
  rig.count = 2;
  rig.width = rig.height = 24;
  Dataset dataset;
  for (const Camera& camera : orbit_cameras(rig)) dataset.train.push_back({"v", camera, Image(24, 24, 3, 0.7f)});
  dataset.test = {dataset.train[0]};
  dataset.scene_extent = 1.1f * rig.radius;
  SplatTrainingConfig config = splat_training_preset("official");
  config.random_init_points = 300;
  config.batch = 2;
  SplatTrainer trainer(dataset, config);
  const GaussianModel start = trainer.model();
  trainer.step();
  EXPECT_EQ(trainer.iteration(), 2);

  Rasterizer rasterizer;
  RenderSettings settings;  // the trainer's at its first step: one SH band, its background
  settings.sh_degree = 0;
  std::copy(config.background, config.background + 3, settings.background);
  settings.alpha_clamp_gradient = config.alpha_clamp_gradient;
  GaussianModel expected;
  for (const DatasetView& view : dataset.train) {
    RenderResult render;
    RasterGradients grads;
    Image v_image;
    SsimScratch scratch;
    rasterizer.render(start, view.camera, settings, render);
    photometric_loss(render.color, view.image, config.ssim_weight, &v_image, scratch);
    rasterizer.backward(start, view.camera, settings, render, v_image, grads);
    if (expected.size() == 0) expected = grads.params;
    else expected.add(grads.params);
  }
  expected.scale(0.5f);
  EXPECT_EQ(flat(trainer.last_step_gradient()), flat(expected));
  EXPECT_NE(flat(expected), std::vector<float>(flat(expected).size(), 0.0f));

  config.iterations = 301;  // iterations count views: a whole number of steps
  EXPECT_THROW(SplatTrainer(dataset, config), ArgumentError);
}

}  // namespace
}  // namespace splat
