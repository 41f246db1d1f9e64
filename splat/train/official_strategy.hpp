#pragma once
// The official 3DGS density control (clone, split, prune, opacity reset on the official
// schedule) behind the strategy interface, bit for bit what DensityControl does: the same
// seed gives the same model as the official recipe always has.
#include "splat/optim/density_control.hpp"
#include "splat/train/density_strategy.hpp"

namespace splat {

class OfficialStrategy final : public DensityStrategy {
 public:
  OfficialStrategy(const DensityControlSettings& settings, std::size_t gaussian_count)
      : control_(settings, gaussian_count) {}

  std::string name() const override { return "official"; }
  DensityStepReport step_post_backward(int iteration, bool last_iteration, TrainingState& state,
                                       GaussianModel& grads, std::span<const BackwardStats> views) override;
  std::vector<std::vector<float>*> checkpoint_arrays() override;
  void checkpoint_loaded(const nlohmann::json& state, std::size_t gaussian_count) override;

  const DensityControl& control() const { return control_; }

 private:
  DensityControl control_;
};

}  // namespace splat
