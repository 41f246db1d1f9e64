#pragma once
// A training step over a batch of B views (`--batch B`): the loss is the mean of the views'
// losses, so the step's gradient is the sum of the views' gradients over B. Its iteration
// count is in views: a step advances it by B, so every schedule keeps its meaning (densify
// every 100 views, grow until view 15,000, ...) whatever the batch, and runs compare at an
// equal number of views seen.
//
// The sum is taken in one fixed order, a pairwise tree over the views in batch order: each
// new view's gradient joins the last partial sum while the two cover equally many views
// (a binary counter), and what is left is added from the right. A run of B views split into K
// contiguous blocks of B/K views, B/K a power of two, makes each block one whole subtree, so
// summing each block on its own and then the K block sums in the same way gives the same
// floats bit for bit: the model does not depend on how the views are shared out (data-parallel
// training, issue 18). The tree is the same for every element, so a slice of the flattened
// values summed on its own (batch_exchange.hpp) gives that slice of the whole sum.
#include <cstddef>
#include <span>
#include <utility>
#include <vector>

#include "splat/core/error.hpp"
#include "splat/gaussians/gaussian_model.hpp"

namespace splat {

// Element-wise a += b, for the buffers a pairwise sum is taken of.
inline void add_into(GaussianModel& a, const GaussianModel& b) { a.add(b); }
void add_into(std::span<float> a, std::span<const float> b);

// The pairwise sum above, of buffers of one shape: GaussianModel-shaped gradients, or spans
// of flattened values, summed in place (the left span of each pair receives the sum).
template <class Buffer>
class PairwiseSum {
 public:
  // Starts an empty sum (keeps the buffers).
  void clear() { count_ = 0; }
  // Adds the next view's gradient (or the next block's sum): copied in, then merged (for
  // spans, take: a span's copy is the same memory).
  void add(const Buffer& gradient) {
    Buffer copy = gradient;
    take(copy);
  }
  // The same without the copy: takes `gradient`'s contents and leaves it a spare buffer of
  // unspecified values (a rasterizer's backward overwrites its gradient whole).
  void take(Buffer& gradient) {
    if (partials_.size() <= count_) {
      partials_.emplace_back();
      views_.push_back(0);
    }
    std::swap(partials_[count_], gradient);
    views_[count_] = 1;
    ++count_;
    // Merge while the last two partial sums cover equally many views: a binary counter.
    while (count_ >= 2 && views_[count_ - 2] == views_[count_ - 1]) {
      add_into(partials_[count_ - 2], partials_[count_ - 1]);
      views_[count_ - 2] *= 2;
      --count_;
    }
  }
  // The sum of everything added (at least one add first), which the caller may change in
  // place (to scale it). It ends the sum: clear() before the next one.
  Buffer& total() {
    if (count_ == 0) throw ArgumentError("PairwiseSum: nothing was added");
    // What is left covers decreasing numbers of views: add from the right, so that the
    // smaller trailing sums meet first (the tree's right spine).
    while (count_ >= 2) {
      add_into(partials_[count_ - 2], partials_[count_ - 1]);
      views_[count_ - 2] += views_[count_ - 1];
      --count_;
    }
    return partials_[0];
  }
  std::size_t count() const { return count_; }

 private:
  // partials_[0 .. count_) hold sums over views_[i] views each, in batch order, sizes
  // strictly decreasing once merged; the buffers beyond count_ are kept for reuse.
  std::vector<Buffer> partials_;
  std::vector<std::size_t> views_;
  std::size_t count_ = 0;
};

using PairwiseGradientSum = PairwiseSum<GaussianModel>;

}  // namespace splat
