#pragma once
// What one training step reports, for both trainers (splats and NeRF): its loss, where its
// time went, what density control did, and the error that stops a run that diverged.
#include <string>
#include <utility>

#include "splat/core/error.hpp"
#include "splat/train/batch_exchange.hpp"
#include "splat/train/density_strategy.hpp"

namespace splat {

// Training produced NaN or Inf: which iteration and which parameter group (or "loss").
class TrainingDiverged : public Error {
 public:
  TrainingDiverged(int iteration, const std::string& group)
      : Error("training diverged at iteration " + std::to_string(iteration) + ": non-finite " +
              group),
        iteration_(iteration), group_(group) {}
  int iteration() const { return iteration_; }
  const std::string& group() const { return group_; }

 private:
  int iteration_;
  std::string group_;
};

struct IterationTimings {  // milliseconds
  double forward = 0, loss = 0, backward = 0, optimizer = 0, densify = 0;
  // The rasterizer's stages inside forward and backward (splats only; 0 for the NeRF).
  double project = 0, bin_sort = 0, blend = 0, blend_backward = 0, project_backward = 0;
  // Over several ranks: exchanging and summing the batch's gradients and statistics (0 alone).
  double exchange = 0;

  // Every figure by name: the five stages, then the rasterizer's parts.
  static constexpr std::pair<const char*, double IterationTimings::*> kFields[] = {
      {"forward", &IterationTimings::forward},         {"loss", &IterationTimings::loss},
      {"backward", &IterationTimings::backward},       {"optimizer", &IterationTimings::optimizer},
      {"densify", &IterationTimings::densify},         {"project", &IterationTimings::project},
      {"bin_sort", &IterationTimings::bin_sort},       {"blend", &IterationTimings::blend},
      {"blend_backward", &IterationTimings::blend_backward},
      {"project_backward", &IterationTimings::project_backward}, {"exchange", &IterationTimings::exchange}};

  double total() const { return forward + loss + backward + exchange + optimizer + densify; }
  IterationTimings& operator+=(const IterationTimings& o) {
    for (const auto& [name, field] : kFields) this->*field += o.*field;
    return *this;
  }
};

struct StepResult {
  double loss = 0, l1 = 0, ssim = 0;
  int resolution_divisor = 1;  // the image trained on was 1/this of the full size
  IterationTimings timings;
  DensityStepReport density;
  ExchangeReport exchange;  // several ranks only
};

}  // namespace splat
