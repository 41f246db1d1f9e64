#pragma once
// The NeRF baseline's trainer: random batches of rays across all training images, the
// coarse and fine networks' colours both fitted with the mean squared error (as the paper),
// Adam with an exponentially decaying learning rate, and the occupancy grid refreshed from
// the networks' densities so that rays skip empty space. No printing: the command line
// reports progress.
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <random>
#include <vector>

#include "splat/data/dataset.hpp"
#include "splat/nerf/nerf_model.hpp"
#include "splat/nerf/nerf_renderer.hpp"
#include "splat/optim/flat_adam.hpp"
#include "splat/train/evaluation.hpp"
#include "splat/train/nerf_training_config.hpp"
#include "splat/train/resume_settings.hpp"
#include "splat/train/step_result.hpp"

namespace splat {

// Where in the rate's decay the parameter average starts (parameter_average_decay).
constexpr double kAverageFromProgress = 0.5;

class NerfTrainer {
 public:
  NerfTrainer(const Dataset& dataset, const NerfTrainingConfig& config);

  // One iteration: a batch of random rays, forward, loss, backward, Adam, maybe a grid
  // update. Throws TrainingDiverged on a non-finite loss or parameter.
  StepResult step();
  // Renders `views` (fine colours) and scores them; `renders` receives the clamped images.
  Evaluation evaluate(const std::vector<DatasetView>& views, std::vector<Image>* renders = nullptr);
  // The image evaluate() scores for one camera (clamped to [0, 1]), without scoring it.
  Image render(const Camera& camera);

  int iteration() const { return iteration_; }
  // The share of the time budget spent (the training loop sets it before each step).
  void set_time_budget_fraction(double fraction) { time_budget_fraction_ = fraction; }
  // The run's model: the parameter average (parameter_average_decay) with the live grid, or
  // Adam's iterate when averaging is off. What is scored, saved and checkpointed as the model.
  const NerfModel& model() const { return config_.parameter_average_decay > 0 ? averaged_ : model_; }
  // The parameters Adam steps (the same as model() without averaging).
  const NerfModel& iterate() const { return model_; }
  const NerfModel& last_good_model() const { return last_good_model_; }
  const NerfTrainingConfig& config() const { return config_; }
  void check_parameters_finite() const { check_finite(iteration_); }
  // Fault injection for the tests of the divergence path: sets one fine-network weight to NaN.
  void inject_non_finite_parameter() { model_.fine.parameters()[0] = std::nanf(""); }
  void save_checkpoint(const std::filesystem::path& file) const;
  // As SplatTrainer::load_checkpoint (checkpoints of version 1 and 2 carry no settings: this
  // run's apply).
  void load_checkpoint(const std::filesystem::path& file, const GivenSettings& given = {});

  // Samples the networks evaluated, summed over this process's steps (a resumed run counts
  // from its resumption): with the step timings, what a sample costs. Each step traces
  // config().rays_per_batch rays.
  struct SampleCounts {
    std::uint64_t steps = 0, coarse = 0, fine = 0;
  };
  const SampleCounts& sample_counts() const { return sample_counts_; }

  // The rate the next step takes (the decay above).
  float learning_rate() const;
  // How far the rate's decay has gone, 0 … 1: the iterations' share of lr_decay_iterations,
  // or under a budget (schedule_follows_budget) the share of the time spent.
  double schedule_progress() const;

 private:
  // Throws TrainingDiverged naming `iteration` and the first network with a non-finite value.
  void check_finite(int iteration) const;
  void update_occupancy();
  // Moves averaged_'s parameters toward model_'s (parameter_average_decay's rule).
  void update_average();

  const Dataset& dataset_;
  NerfTrainingConfig config_;
  NerfModel model_, averaged_, last_good_model_;
  FlatAdam coarse_adam_, fine_adam_;
  std::mt19937 rng_;
  int iteration_ = 0;
  double time_budget_fraction_ = 0;
  SampleCounts sample_counts_;
  NerfRenderer renderer_;
  NerfForwardContext forward_;  // the training batch's forward, and the scoring renders'
  std::vector<Ray> rays_;
  std::vector<float> ray_backgrounds_;  // [R, 3] with random_background
  std::vector<float> targets_, v_coarse_, v_fine_, coarse_grad_, fine_grad_;
  // One per network: a context sized for the other network's shape is rebuilt from scratch,
  // and sharing one reallocated ~100 MB every grid update (8 % of a run in page faults).
  NerfMlpContext coarse_density_context_, fine_density_context_;
  std::vector<float> density_positions_, density_sigma_, density_max_;
};

}  // namespace splat
