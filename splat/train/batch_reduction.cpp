#include "splat/train/batch_reduction.hpp"

#include <string>

#include "splat/core/error.hpp"

namespace splat {

void BatchReduction::set_process_group(ProcessGroup* group, int views) {
  if (group && group->size() > 1) {
    const int ranks = group->size();
    if (views % ranks != 0 || ((views / ranks) & (views / ranks - 1)) != 0)
      throw ArgumentError("--batch " + std::to_string(views) + " over " + std::to_string(ranks) +
                          " ranks: each rank takes batch / ranks views, which must be a whole power of two "
                          "(1, 2, 4, ...) so that the model does not depend on the number of ranks");
  }
  group_ = group && group->size() > 1 ? group : nullptr;
}

void BatchReduction::start(int views) {
  views_ = views;
  gradient_sum_.clear();
  view_stats_.resize(std::size_t(views));
}

void BatchReduction::add(int v, const LossValue& loss, ViewStep& step) {
  ViewStatistics& stats = view_stats_[std::size_t(v)];
  stats.loss = loss;
  if (views_ == 1) return;  // read where they are, in reduce()
  RasterGradients& grads = step.gradients();
  gradient_sum_.take(grads.params);
  stats.viewspace_grad_norm = grads.viewspace_grad_norm;
  stats.radii = step.render().frame.projected.radius;
  stats.blend_weight = grads.blend_weight;
  stats.width = step.render().color.width;
  stats.height = step.render().color.height;
}

ReducedBatch BatchReduction::reduce(ViewStep& step) {
  ExchangeReport exchange;
  // The mean loss's gradient: the views' sum over the batch (a single view's as it is).
  GaussianModel* gradient = &step.gradients().params;
  if (views_ > 1) {
    if (group_) {
      gradient = &exchange_.exchange(*group_, gradient_sum_.total(), view_stats_);
      exchange = exchange_.last_report();
    } else {
      gradient = &gradient_sum_.total();
    }
    gradient->multiply(1.0f / float(views_));
  }
  LossValue mean;
  for (const ViewStatistics& stats : view_stats_) {
    mean.loss += stats.loss.loss / views_;
    mean.l1 += stats.loss.l1 / views_;
    mean.ssim += stats.loss.ssim / views_;
  }

  backward_stats_.clear();
  if (views_ == 1) {
    const RasterGradients& grads = step.gradients();
    backward_stats_.push_back({grads.viewspace_grad_norm, step.render().frame.projected.radius, grads.blend_weight,
                               step.render().color.width, step.render().color.height});
  } else {
    for (const ViewStatistics& v : view_stats_)
      backward_stats_.push_back({v.viewspace_grad_norm, v.radii, v.blend_weight, v.width, v.height});
  }
  const RasterGradients& view = step.gradients();
  const ShGradientFactors* sh_factors = views_ == 1 && view.sh_as_factors ? &view.sh_factors : nullptr;
  return {*gradient, backward_stats_, mean, exchange, sh_factors};
}

}  // namespace splat
