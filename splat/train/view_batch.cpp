#include "splat/train/view_batch.hpp"

#include <utility>

#include "splat/core/error.hpp"

namespace splat {

void PairwiseGradientSum::add(const GaussianModel& gradient) {
  GaussianModel copy = gradient;
  take(copy);
}

void PairwiseGradientSum::take(GaussianModel& gradient) {
  if (partials_.size() <= count_) {
    partials_.emplace_back();
    views_.push_back(0);
  }
  std::swap(partials_[count_], gradient);
  views_[count_] = 1;
  ++count_;
  // Merge while the last two partial sums cover equally many views: a binary counter.
  while (count_ >= 2 && views_[count_ - 2] == views_[count_ - 1]) {
    partials_[count_ - 2].add(partials_[count_ - 1]);
    views_[count_ - 2] *= 2;
    --count_;
  }
}

GaussianModel& PairwiseGradientSum::total() {
  if (count_ == 0) throw ArgumentError("PairwiseGradientSum: nothing was added");
  // What is left covers decreasing numbers of views: add from the right, so that the
  // smaller trailing sums meet first (the tree's right spine).
  while (count_ >= 2) {
    partials_[count_ - 2].add(partials_[count_ - 1]);
    views_[count_ - 2] += views_[count_ - 1];
    --count_;
  }
  return partials_[0];
}

}  // namespace splat
