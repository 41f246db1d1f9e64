#include "splat/train/nerf_training_config.hpp"

#include "splat/core/settings_table.hpp"
#include "splat/nerf/nerf_file.hpp"

namespace splat {

// Every setting: its key in config.json, its member and its allowed values (the members'
// initialisers are the defaults).
template <class Table>
void describe_settings(Table& t, NerfTrainingConfig& c) {
  using namespace setting_ranges;
  t.constant("method", "nerf");
  t.number("iterations", c.iterations, kPositiveIterations);
  t.number("max_seconds", c.max_seconds, kSeconds);
  t.triple("background", c.background, kUnit);
  t.number("seed", c.seed, kSeed);
  t.number("rays_per_batch", c.rays_per_batch, {1, kMaxNerfRaysPerBatch});
  t.number("lr_init", c.lr_init, kLogScheduleRate);
  t.number("lr_final", c.lr_final, kLogScheduleRate);
  t.number("lr_decay_iterations", c.lr_decay_iterations, kPositiveIterations);
  t.flag("schedule_follows_budget", c.schedule_follows_budget);
  t.number("parameter_average_decay", c.parameter_average_decay, {0, 0.99999});
  t.number("density_bias_init", c.density_bias_init, {-100, 100});
  t.number("occupancy_warmup", c.occupancy_warmup, kIterations);
  t.number("occupancy_interval", c.occupancy_interval, kPositiveIterations);
  t.number("occupancy_cells_per_update", c.occupancy_cells_per_update, {0, 16'777'216});  // 256³
  t.number("test_interval", c.test_interval, kIterations);
  t.number("checkpoint_interval", c.checkpoint_interval, kIterations);
  t.flag("box_from_data", c.box_from_data);
  t.section("model", c.model, read_nerf_settings);
}

void validate(const NerfTrainingConfig& config) {
  check_setting_ranges(config);
  validate(config.model, "model");
}

nlohmann::json to_json(const NerfTrainingConfig& config) { return settings_json(config); }

void from_json(const nlohmann::json& json, NerfTrainingConfig& config) {
  // A box given in "model" is kept as given: it turns box_from_data off unless the file says
  // box_from_data too (as the config.json a run writes does).
  bool box_given = false;
  if (json.is_object())
    if (const auto model = json.find("model"); model != json.end() && model->is_object())
      box_given = model->contains("box_min") || model->contains("box_max") || model->contains("unbounded");
  read_settings(json, config, {.what = "the NeRF config", .unknown = "unknown NeRF setting"});
  if (box_given && !json.contains("box_from_data")) config.box_from_data = false;
}

}  // namespace splat
