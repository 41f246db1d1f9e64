#pragma once
// Every setting of the NeRF trainer (nerf_trainer.hpp) in one struct with its defaults, the
// model's (NerfSettings) among them. The command line fills it and it is written beside the
// outputs (config.json); its table of keys and ranges (nerf_training_config.cpp,
// splat/core/settings_table.hpp) reads, writes and validates it.
#include <cstddef>
#include <string>

#include <nlohmann/json.hpp>

#include "splat/nerf/nerf_model.hpp"
#include "splat/train/training_limits.hpp"

namespace splat {

// The iteration limit of a NeRF run with a time budget and no iteration count of its own.
constexpr int kNerfIterationsUnderBudget = kMaxTrainingIterations;
// The largest batch: its samples' activations grow with it (docs/DESIGN.md §4.7).
constexpr int kMaxNerfRaysPerBatch = 16384;

// The radiance-field methods this config trains: "nerf" (the MLP baseline) and "ngp" (the
// hash-encoded networks; nerf_training_preset gives their defaults).
inline constexpr const char* kNerfMethods[] = {"nerf", "ngp"};

struct NerfTrainingConfig {
  std::string method = "nerf";  // fixed by the preset: a config file must name the same
  int iterations = 20000;
  double max_seconds = 0;  // wall-clock limit, 0 = none; whichever ends first
  float background[3] = {1, 1, 1};
  // Training rays through pixels that the photo leaves transparent (its alpha channel) see a
  // random colour behind them, one per ray, and the target is the photo composited onto that
  // colour (Instant-NGP's trick): the only field that matches every such ray is one that is
  // empty along it. With a fixed background a fog of that colour matches as well, and on
  // few training views a hash field learns one (few_views: 16.4 dB, a coloured haze). Photos
  // without transparency train as before; test views are scored on `background`.
  bool random_background = false;
  unsigned seed = 0;
  int rays_per_batch = 1024;
  // Exponential decay from lr_init to lr_final over lr_decay_iterations (then held), a
  // horizon of its own so that --iters and --resume do not change the schedule. With a time
  // budget and schedule_follows_budget, the decay runs over the budget instead (the fraction
  // of it spent), so a run of any length ends at lr_final, and a long one at its end: taking
  // the iterations' fraction when further along held lego400's 30-minute run (45k
  // iterations) at lr_final from 20k on, where its loss stopped falling. Ten times
  // the paper's rates: with a batch of 1,024 rays they reach a given PSNR in a fraction of
  // the time and stay stable (lego400 after 1,000 iterations: 21.08 dB, the paper's
  // 5e-4 → 5e-5 19.10; in 10 minutes twice these rates scored 24.21 dB against 24.39).
  double lr_init = 5e-3, lr_final = 2.5e-4;
  // Adam's β2 and ε (β1 is 0.9). A hash table's entries see gradients only from the samples
  // that fall near them, often 10⁻⁶ and smaller: an ε of 10⁻⁷ would damp their steps to a
  // fraction of the rate, so the NGP preset takes the paper's 10⁻¹⁵ (and β2 = 0.99, whose
  // shorter memory suits gradients that come and go with the batches).
  double adam_beta2 = 0.999, adam_epsilon = 1e-7;
  int lr_decay_iterations = 20000;
  bool schedule_follows_budget = true;
  // The density output's bias at initialisation (both networks). With 0 (a Glorot network's
  // zero bias) the untrained field is a fog of σ ≈ 0.7 that turns every ray grey; clearing it
  // is the first thing training does, with large gradients that drive the softplus deep into
  // its flat tail and inflate Adam's second moments, after which thin structures against a
  // bright background never get drawn (thin_structures stayed at the background's PSNR,
  // 17.18 dB, where −3 reached 24.78 dB in 400 iterations).
  // At −3 (σ ≈ 0.05 per unit) the field starts nearly transparent: there is no fog to clear
  // and density grows only where the photographs ask for it.
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
  // the average against the iterate of the same run: +0.21 and +0.13 dB (0.999: +0.05–0.18;
  // longer averages reach back to worse iterates).
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

// The defaults of `method` ("nerf": the members' initialisers; "ngp": Instant-NGP's
// multiresolution hash encoding in front of tiny networks). ArgumentError for another name.
NerfTrainingConfig nerf_training_preset(const std::string& method);

// Throws ArgumentError naming the first setting outside its range (the ranges a config file
// is read with), the model's included. The trainer calls it.
void validate(const NerfTrainingConfig& config);

// Every setting, "method" among them.
nlohmann::json to_json(const NerfTrainingConfig& config);
// Reads the keys present over `config`: ArgumentError naming an unknown key or a bad value,
// or a "method" other than config.method (a file for the NeRF does not turn a run into NGP
// half-way: the preset comes from the command line). "model" is merged key by key over the
// current settings.
void from_json(const nlohmann::json& json, NerfTrainingConfig& config);

}  // namespace splat
