#pragma once
// Adam over one flat parameter vector (the NeRF's MLP weights live in a single array), with
// PyTorch's update rule:
//   m ← β1·m + (1 − β1)·g,  v ← β2·v + (1 − β2)·g²,
//   p ← p − lr/(1 − β1ᵗ) · m / (sqrt(v)/sqrt(1 − β2ᵗ) + ε).
// Element-wise, so parallel chunks give the same result for any thread count.
#include <cstddef>
#include <span>
#include <vector>

namespace splat {

struct FlatAdamSettings {
  double beta1 = 0.9, beta2 = 0.999, epsilon = 1e-7;  // ε as the NeRF paper's
};

class FlatAdam {
 public:
  FlatAdam() = default;
  explicit FlatAdam(std::size_t size, FlatAdamSettings settings = {})
      : settings_(settings), m_(size, 0.0f), v_(size, 0.0f) {}

  // One step on `params` with gradient `grad` (same size as the constructor's).
  void step(std::span<float> params, std::span<const float> grad, float learning_rate);

  std::size_t size() const { return m_.size(); }
  long long steps() const { return step_count_; }

  // State for checkpoints: the moments and the step count.
  std::vector<float>& first_moment() { return m_; }
  std::vector<float>& second_moment() { return v_; }
  const std::vector<float>& first_moment() const { return m_; }
  const std::vector<float>& second_moment() const { return v_; }
  void set_steps(long long steps) { step_count_ = steps; }

 private:
  FlatAdamSettings settings_;
  std::vector<float> m_, v_;
  long long step_count_ = 0;
};

}  // namespace splat
