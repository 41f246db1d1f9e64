#pragma once
// The NeRF baseline's trainer: random batches of rays across all training images, the
// coarse and fine networks' colours both fitted with the mean squared error (as the paper),
// Adam with an exponentially decaying learning rate, and the occupancy grid refreshed from
// the networks' densities so that rays skip empty space. No printing: the command line
// reports progress.
#include <cmath>
#include <filesystem>
#include <random>
#include <vector>

#include "splat/data/dataset.hpp"
#include "splat/nerf/nerf_model.hpp"
#include "splat/nerf/nerf_renderer.hpp"
#include "splat/optim/flat_adam.hpp"
#include "splat/train/evaluation.hpp"
#include "splat/train/step_result.hpp"
#include "splat/train/training_config.hpp"

namespace splat {

// The iteration limit of a NeRF run with a time budget and no iteration count of its own.
constexpr int kNerfIterationsUnderBudget = kMaxTrainingIterations;
// Where in the rate's decay the parameter average starts (parameter_average_decay).
constexpr double kAverageFromProgress = 0.5;
// The largest batch: its samples' activations grow with it (docs/DESIGN.md §4.7).
constexpr int kMaxNerfRaysPerBatch = 16384;

struct NerfTrainingConfig {
  int iterations = 20000;
  double max_seconds = 0;  // wall-clock limit, 0 = none; whichever ends first
  float background[3] = {1, 1, 1};
  unsigned seed = 0;
  int rays_per_batch = 1024;
  // Exponential decay from lr_init to lr_final over lr_decay_iterations (then held), a
  // horizon of its own so that --iters and --resume do not change the schedule. With a time
  // budget and schedule_follows_budget, the decay runs over the budget instead (the fraction
  // of it spent), so a run of any length ends at lr_final, and a long one at its end: taking
  // the iterations' fraction when further along held lego400's 30-minute run (45k
  // iterations) at lr_final from 20k on, where its loss stopped falling. Ten times
  // the paper's rates: with a batch of 1,024 rays they reach a given PSNR in a fraction of
  // the time and stay stable (probes in bench/README.md, P4).
  double lr_init = 5e-3, lr_final = 2.5e-4;
  int lr_decay_iterations = 20000;
  bool schedule_follows_budget = true;
  // The density output's bias at initialisation (both networks). With 0 (a Glorot network's
  // zero bias) the untrained field is a fog of σ ≈ 0.7 that turns every ray grey; clearing it
  // is the first thing training does, with large gradients that drive the softplus deep into
  // its flat tail and inflate Adam's second moments, after which thin structures against a
  // bright background never get drawn (thin_structures stayed at the background's PSNR).
  // At −3 (σ ≈ 0.05 per unit) the field starts nearly transparent: there is no fog to clear
  // and density grows only where the photographs ask for it (bench/README.md, issue 16).
  float density_bias_init = -3.0f;
  // Iterations before the grid first prunes. Early, since it only drops cells fainter than
  // the mean (occupancy_grid.hpp): lego400 scores the same at 3,000 iterations as with 256,
  // and a model is cheap to score from the start.
  int occupancy_warmup = 16;
  int occupancy_interval = 16;             // iterations between grid updates
  std::size_t occupancy_cells_per_update = 1 << 16;
  // The model a run scores and saves is an exponential moving average of the parameters
  // Adam steps through (Polyak averaging): the last steps, even at lr_final, scatter the
  // networks around the minimum by their gradient noise, and their mean sits nearer to it.
  // From halfway through the rate's decay (kAverageFromProgress) each step moves the average
  // (1 − this) of the way to the parameters, so it spans the last ~1/(1 − this) steps; before
  // that it is the parameters. 0 = off (the model is Adam's iterate). lego400, 15-minute runs,
  // the average against the iterate of the same run: bench/README.md, issue 16.
  float parameter_average_decay = 0.998f;
  int test_interval = 2000;       // iterations between test evaluations (0 = end only)
  int checkpoint_interval = 5000;  // iterations between checkpoints (0 = none)
  // Where rays sample follows the dataset (the cameras, or the point cloud:
  // nerf_scene_space.hpp) rather than model.box. A config that sets the model's box_min,
  // box_max or unbounded turns this off (an explicit box is kept as given) unless it also
  // says box_from_data, as the config.json a run writes does.
  bool box_from_data = true;
  NerfSettings model;
};

nlohmann::json to_json(const NerfTrainingConfig& config);
// Reads the fields present over `config`; ArgumentError naming an unknown key or bad value.
void from_json(const nlohmann::json& json, NerfTrainingConfig& config);

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
  void load_checkpoint(const std::filesystem::path& file);

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
  NerfRenderer renderer_;
  NerfForwardContext forward_;  // the training batch's forward, and the scoring renders'
  std::vector<Ray> rays_;
  std::vector<float> targets_, v_coarse_, v_fine_, coarse_grad_, fine_grad_;
  // One per network: a context sized for the other network's shape is rebuilt from scratch,
  // and sharing one reallocated ~100 MB every grid update (8 % of a run in page faults).
  NerfMlpContext coarse_density_context_, fine_density_context_;
  std::vector<float> density_positions_, density_sigma_, density_max_;
};

}  // namespace splat
