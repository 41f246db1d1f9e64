#pragma once
// One step's batch of views, reduced to what the step takes: the mean of the views'
// gradients (their pairwise sum, view_batch.hpp, over the batch's size), the views' mean loss,
// and every view's statistics for the density strategy. Over several ranks each renders its
// own block of the views, and the exchange (batch_exchange.hpp) gives every rank the whole
// batch's. A batch of one view reduces to that view's own buffers, copied nowhere.
#include <span>
#include <vector>

#include "splat/gaussians/gaussian_model.hpp"
#include "splat/optim/photometric_loss.hpp"
#include "splat/train/batch_exchange.hpp"
#include "splat/train/density_strategy.hpp"
#include "splat/train/process_group.hpp"
#include "splat/train/view_batch.hpp"
#include "splat/train/view_step.hpp"

namespace splat {

struct ReducedBatch {
  GaussianModel& gradient;               // the mean of the views' gradients, which the caller may change
  std::span<const BackwardStats> views;  // every view's statistics, in batch order
  LossValue loss;                        // the mean of the views' losses
  ExchangeReport exchange;               // several ranks only
  // A single view differentiated with its SH gradient in factored form: those factors, and
  // gradient.sh is not to be read. Null otherwise.
  const ShGradientFactors* sh_factors = nullptr;
};

class BatchReduction {
 public:
  // Shares each batch of `views` views with the other ranks of `group` (null or a group of
  // one: this process takes them all). ArgumentError unless views / ranks is a whole power of
  // two, which is what makes the sum, and so the model, the same for any number of ranks.
  void set_process_group(ProcessGroup* group, int views);
  int ranks() const { return group_ ? group_->size() : 1; }

  // Starts a batch of `views` views.
  void start(int views);
  // The views of the batch this process renders: [first(), first() + count()).
  int first() const { return group_ ? group_->rank() * count() : 0; }
  int count() const { return views_ / ranks(); }

  // View `v` of the batch, just differentiated by `step`. In a batch of several its gradient
  // and statistics are taken out of the step's buffers, which the next view reuses.
  void add(int v, const LossValue& loss, ViewStep& step);

  // The batch reduced (collective over the ranks). The gradient and statistics are valid
  // until the next batch starts; for a single view they are `step`'s own.
  ReducedBatch reduce(ViewStep& step);

 private:
  ProcessGroup* group_ = nullptr;  // null: this process takes every view
  int views_ = 1;
  std::vector<ViewStatistics> view_stats_;     // [view of the batch]
  std::vector<BackwardStats> backward_stats_;  // views of view_stats_ (or of the step's buffers)
  PairwiseGradientSum gradient_sum_;
  BatchExchange exchange_;
};

}  // namespace splat
