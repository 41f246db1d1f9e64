#pragma once
// What the ranks of a data-parallel step (issue 18) send each other: every rank has rendered
// and differentiated its block of B/K views; afterwards every rank must hold the batch's
// gradient sum (the same floats as one process summing all B views, view_batch.hpp) and every
// view's statistics (the density strategy's decisions read them).
//
// The gradient goes in two collectives, so that what a rank sends does not grow with K (a
// ring all-reduce's volume), where gathering every block on every rank sends K − 1 whole
// gradients:
//  1. all-to-all: the flattened values are cut into K equal slices; rank q receives slice q
//     of every rank's block sum and adds the K of them through the pairwise sum, in rank
//     order (the tree is the same for every element, so this is slice q of the whole sum);
//  2. all-gather: each rank's summed slice goes to every rank, which puts them back
//     together; a second all-gather does the same with every rank's views' statistics.
// A rank sends about 2·(K − 1)/K of a gradient plus (K − 1) × its views' statistics.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "splat/gaussians/gaussian_model.hpp"
#include "splat/optim/photometric_loss.hpp"
#include "splat/train/process_group.hpp"
#include "splat/train/view_batch.hpp"

namespace splat {

// One view's results in a batch, kept until the step's density decision (the rasterizer's
// buffers are reused by the next view).
struct ViewStatistics {
  LossValue loss;
  std::vector<float> viewspace_grad_norm, blend_weight;
  std::vector<std::int32_t> radii;
  int width = 0, height = 0;
};

// What one exchange cost, and what a sparse one would: the rows a view of this rank's block,
// or of the whole batch, drew (radius > 0; the others' gradient rows and statistics are zero).
struct ExchangeReport {
  std::size_t bytes_sent = 0;  // this rank's messages, times the ranks each went to
  std::size_t rows = 0;        // Gaussians
  std::size_t block_visible_rows = 0, batch_visible_rows = 0;
};

class BatchExchange {
 public:
  // `block`: this rank's pairwise sum of its views' gradients; `views`: the batch's views in
  // order, of which this rank's block (views.size() / group.size() of them, starting at
  // rank × that) are filled in. Returns the batch's gradient sum, valid until the next call
  // (the caller may scale it), and fills in every view. Collective: every rank calls it.
  GaussianModel& exchange(ProcessGroup& group, const GaussianModel& block, std::span<ViewStatistics> views);
  const ExchangeReport& last_report() const { return report_; }

 private:
  std::vector<float> slices_out_, slices_in_;
  PairwiseSum<std::span<float>> slice_sum_;  // in place, over slices_in_
  std::vector<float> summed_slices_, views_out_, views_in_;
  GaussianModel total_;
  std::vector<std::uint8_t> drawn_;  // [N]: 1 drawn by the block, 2 by the batch
  ExchangeReport report_;
};

}  // namespace splat
