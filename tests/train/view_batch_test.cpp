// Batches of views: events fall in the step whose views hold them, the batch's gradient is
// one fixed pairwise sum that blocks of the batch reproduce bit for bit (what makes a model
// independent of how many ranks share the views), and a trainer's batch step takes the mean
// of its views' gradients.
#include "splat/train/view_batch.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <barrier>
#include <cmath>
#include <random>
#include <thread>
#include <vector>

#include "splat/data/orbit_cameras.hpp"
#include "splat/optim/photometric_loss.hpp"
#include "splat/optim/step_events.hpp"
#include "splat/raster/rasterizer.hpp"
#include "splat/train/batch_exchange.hpp"
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
    if (batch > 2) {
      EXPECT_NE(flat(left), expected) << "batch " << batch;
    }

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

// K threads standing in for K MPI ranks: each collective posts every rank's part on a shared
// board and waits until all have, as the MPI calls do.
class ThreadRanks {
 public:
  explicit ThreadRanks(int ranks) : ranks_(ranks), barrier_(ranks), posted_(std::size_t(ranks)) {}

  class Rank final : public ProcessGroup {
   public:
    Rank(ThreadRanks& board, int rank) : board_(board), rank_(rank) {}
    int rank() const override { return rank_; }
    int size() const override { return board_.ranks_; }
    void all_gather(std::span<const float> mine, std::span<float> all) override {
      post(mine);
      for (int q = 0; q < size(); ++q) std::copy(part(q).begin(), part(q).end(), all.begin() + q * mine.size());
      board_.barrier_.arrive_and_wait();
    }
    void all_to_all(std::span<const float> send, std::span<float> receive) override {
      post(send);
      const std::size_t each = send.size() / std::size_t(size());
      for (int q = 0; q < size(); ++q)
        std::copy_n(part(q).begin() + rank_ * each, each, receive.begin() + q * each);
      board_.barrier_.arrive_and_wait();
    }
    void broadcast(std::span<double>) override { FAIL() << "not used by the exchange"; }
    bool any(bool) override { ADD_FAILURE() << "not used by the exchange"; return false; }

   private:
    void post(std::span<const float> values) {
      board_.posted_[std::size_t(rank_)].assign(values.begin(), values.end());
      board_.barrier_.arrive_and_wait();
    }
    const std::vector<float>& part(int q) const { return board_.posted_[std::size_t(q)]; }
    ThreadRanks& board_;
    int rank_;
  };

 private:
  int ranks_;
  std::barrier<> barrier_;
  std::vector<std::vector<float>> posted_;
};

ViewStatistics random_view(std::mt19937& rng, std::size_t n) {
  std::uniform_real_distribution<float> value(0.0f, 3.0f);
  ViewStatistics view;
  view.loss = {value(rng) / 7.0, value(rng) / 11.0, value(rng) / 13.0};  // doubles that floats do not hold
  view.width = int(rng() % 2000);
  view.height = int(rng() % 2000);
  for (std::size_t i = 0; i < n; ++i) {
    view.viewspace_grad_norm.push_back(value(rng));
    view.blend_weight.push_back(value(rng));
    view.radii.push_back(rng() % 4 == 0 ? 0 : std::int32_t(rng() % 5000));  // a quarter not drawn
  }
  return view;
}

bool same(const ViewStatistics& a, const ViewStatistics& b) {
  return a.loss.loss == b.loss.loss && a.loss.l1 == b.loss.l1 && a.loss.ssim == b.loss.ssim && a.width == b.width &&
         a.height == b.height && a.viewspace_grad_norm == b.viewspace_grad_norm && a.blend_weight == b.blend_weight &&
         a.radii == b.radii;
}

// Every rank ends with the whole batch's pairwise sum, bit for bit, and every view's
// statistics, for gradients whose value count K does not divide (the last slice padded), and
// sends about two gradients' worth.
TEST(BatchExchange, EveryRankGetsTheWholeBatchsSumAndEveryViewBitForBit) {
  std::mt19937 rng(5);
  const std::size_t n = 7;  // 7 × 23 = 161 values at SH degree 1
  for (const auto& [batch_views, rank_count] : {std::pair{2, 2}, {4, 2}, {4, 4}, {8, 4}, {6, 3}}) {
    const int batch = batch_views, ranks = rank_count;  // plain variables: the threads capture them
    std::vector<GaussianModel> gradients;
    std::vector<ViewStatistics> views;
    for (int v = 0; v < batch; ++v) {
      gradients.push_back(random_gradient(rng, n));
      views.push_back(random_view(rng, n));
    }
    PairwiseGradientSum whole;
    for (const GaussianModel& g : gradients) whole.add(g);
    const std::vector<float> expected = flat(whole.total());

    ThreadRanks board(ranks);
    const std::size_t k = std::size_t(ranks);
    std::vector<std::vector<float>> sums(k);
    std::vector<std::vector<ViewStatistics>> received(k);
    std::vector<ExchangeReport> reports(k);
    std::vector<std::thread> threads;
    for (int r = 0; r < ranks; ++r)
      threads.emplace_back([&, r] {
        const int per_rank = batch / ranks;
        PairwiseGradientSum block;
        std::vector<ViewStatistics> mine(static_cast<std::size_t>(batch));  // only this rank's block filled in
        for (int v = r * per_rank; v < (r + 1) * per_rank; ++v) {
          block.add(gradients[std::size_t(v)]);
          mine[std::size_t(v)] = views[std::size_t(v)];
        }
        ThreadRanks::Rank group(board, r);
        BatchExchange exchange;
        sums[std::size_t(r)] = flat(exchange.exchange(group, block.total(), mine));
        received[std::size_t(r)] = mine;
        reports[std::size_t(r)] = exchange.last_report();
      });
    for (std::thread& t : threads) t.join();

    const std::size_t gradient_bytes = 4 * expected.size(), view_bytes = 4 * (8 + 3 * n);
    for (int r = 0; r < ranks; ++r) {
      EXPECT_EQ(sums[std::size_t(r)], expected) << "batch " << batch << ", rank " << r << " of " << ranks;
      for (int v = 0; v < batch; ++v)
        EXPECT_TRUE(same(received[std::size_t(r)][std::size_t(v)], views[std::size_t(v)]))
            << "batch " << batch << ", rank " << r << " of " << ranks << ", view " << v;
      // About two gradients' worth and the rank's views to each other rank; gathering
      // every block on every rank would send K − 1 gradients.
      const std::size_t views_per_rank = std::size_t(batch / ranks);
      const ExchangeReport& report = reports[std::size_t(r)];
      EXPECT_LE(report.bytes_sent, 2 * (gradient_bytes + 4 * k) + (k - 1) * views_per_rank * view_bytes);
      if (ranks > 2) {
        EXPECT_LT(report.bytes_sent, (k - 1) * (gradient_bytes + views_per_rank * view_bytes));
      }
      // The rows a sparse exchange would send: drawn by a view of the block, of the batch.
      std::size_t in_block = 0, in_batch = 0;
      for (std::size_t i = 0; i < n; ++i) {
        bool block = false, batch_drawn = false;
        for (std::size_t v = 0; v < views.size(); ++v) {
          const bool drawn = views[v].radii[i] > 0;
          batch_drawn |= drawn;
          block |= drawn && v / views_per_rank == std::size_t(r);
        }
        in_block += block;
        in_batch += batch_drawn;
      }
      EXPECT_EQ(report.rows, n);
      EXPECT_EQ(report.block_visible_rows, in_block);
      EXPECT_EQ(report.batch_visible_rows, in_batch);
    }
  }
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
  expected.multiply(0.5f);
  EXPECT_EQ(flat(trainer.last_step_gradient()), flat(expected));
  EXPECT_NE(flat(expected), std::vector<float>(flat(expected).size(), 0.0f));

  config.iterations = 301;  // iterations count views: a whole number of steps
  EXPECT_THROW(SplatTrainer(dataset, config), ArgumentError);
}

}  // namespace
}  // namespace splat
