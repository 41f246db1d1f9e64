#include "splat/train/nerf_training_config.hpp"

#include "splat/core/error.hpp"
#include "splat/core/settings_table.hpp"
#include "splat/nerf/nerf_file.hpp"

namespace splat {

// Every setting: its key in config.json, its member and its allowed values (the members'
// initialisers are the defaults).
template <class Table>
void describe_settings(Table& t, NerfTrainingConfig& c) {
  using namespace setting_ranges;
  t.choice("method", c.method, kNerfMethods);
  t.number("iterations", c.iterations, kPositiveIterations);
  t.number("max_seconds", c.max_seconds, kSeconds);
  t.triple("background", c.background, kUnit);
  t.flag("random_background", c.random_background);
  t.number("seed", c.seed, kSeed);
  t.number("rays_per_batch", c.rays_per_batch, {1, kMaxNerfRaysPerBatch});
  t.number("lr_init", c.lr_init, kLogScheduleRate);
  t.number("lr_final", c.lr_final, kLogScheduleRate);
  t.number("lr_decay_iterations", c.lr_decay_iterations, kPositiveIterations);
  t.number("adam_beta2", c.adam_beta2, {0, 0.999999});
  t.number("adam_epsilon", c.adam_epsilon, {0, 1});
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

NerfTrainingConfig nerf_training_preset(const std::string& method) {
  NerfTrainingConfig c;
  if (method == "nerf") return c;
  if (method != "ngp") throw ArgumentError("unknown NeRF method '" + method + "' (nerf or ngp)");
  c.method = "ngp";
  // Instant-NGP (Müller et al. 2022, section 5.4): 16 levels of 2 features from 16 to the
  // finest resolution, one hidden layer of 64 for the density and two-ish for the colour.
  // Here the colour network is the MLP's feature and colour layers (nerf_mlp.hpp), and the
  // coarse network of the hierarchical sampling is a smaller hash field of its own that only
  // has to say where along the ray the surface lies (as nerfacto's proposal networks).
  NerfMlpConfig fine;
  fine.encoding = PositionEncoding::kHash;
  fine.hash = HashEncodingSettings{};
  fine.depth = 1;
  fine.width = 64;
  fine.skip_layer = -1;
  fine.color_width = 64;
  fine.direction_frequencies = 4;
  NerfMlpConfig coarse = fine;
  coarse.hash.levels = 8;
  coarse.hash.table_log2 = 16;
  coarse.hash.max_resolution = 128;
  coarse.width = 32;
  coarse.color_width = 32;
  c.model.coarse = coarse;
  c.model.fine = fine;
  c.model.coarse_samples = 96;
  c.model.fine_samples = 32;
  c.model.occupancy_resolution = 64;
  // The field starts as a uniform fog; the first update already finds where it thins out, and
  // every step before it evaluates all 96 samples of every ray (4 s each on lego400).
  c.occupancy_warmup = 1;
  c.rays_per_batch = 4096;
  c.lr_init = 1e-2;
  c.lr_final = 1e-3;
  c.adam_beta2 = 0.99;
  c.adam_epsilon = 1e-15;
  c.parameter_average_decay = 0;
  c.random_background = true;
  return c;
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
  const std::string method = config.method;
  read_settings(json, config, {.what = "the NeRF config", .unknown = "unknown NeRF setting"});
  if (config.method != method)
    throw ArgumentError("\"method\" is \"" + config.method + "\" where this run trains \"" + method +
                        "\" (the command line's --method picks the method and its defaults)");
  if (box_given && !json.contains("box_from_data")) config.box_from_data = false;
}

}  // namespace splat
