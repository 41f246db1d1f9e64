// Config files are checked as they are read: every value a run cannot use (out of its
// range, not whole where a count is meant, of the wrong type, or an unknown key) is an
// ArgumentError naming the key, for the splat trainer's settings and the NeRF's alike.
#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "splat/train/nerf_trainer.hpp"
#include "splat/train/training_config.hpp"

namespace splat {
namespace {

struct BadSetting {
  const char* json;
  const char* key;  // the error must name it
};

template <class Config>
void expect_rejected(const BadSetting& bad, Config config) {
  try {
    from_json(nlohmann::json::parse(bad.json), config);
    ADD_FAILURE() << bad.json << " was accepted";
  } catch (const ArgumentError& e) {
    EXPECT_NE(std::string(e.what()).find(bad.key), std::string::npos) << bad.json << " -> " << e.what();
  }
}

TEST(ConfigLimits, SplatSettingsOutsideTheirRangesAreRejectedNamingTheKey) {
  const BadSetting cases[] = {
      {R"({"iterations": -5})", "iterations"},
      {R"({"iterations": 3.5})", "iterations"},
      {R"({"iterations": 1e30})", "iterations"},
      {R"({"iterations": "many"})", "iterations"},
      {R"({"position_lr_init": -1e-4})", "position_lr_init"},
      {R"({"position_lr_final": 0})", "position_lr_final"},  // a log-linear end point
      {R"({"opacity_lr": 1e9})", "opacity_lr"},
      {R"({"ssim_weight": 2})", "ssim_weight"},
      {R"({"background_g": 5})", "background_g"},
      {R"({"densification_interval": 0})", "densification_interval"},
      {R"({"sh_increase_interval": 0})", "sh_increase_interval"},
      {R"({"compact_grow_interval": 0})", "compact_grow_interval"},
      {R"({"sh_degree": 9})", "sh_degree"},
      {R"({"random_init_points": 1e12})", "random_init_points"},
      {R"({"opacity_reset_value": 1})", "opacity_reset_value"},
      {R"({"seed": -1})", "seed"},
      {R"({"max_seconds": -3})", "max_seconds"},
      {R"({"refine_poses": 1})", "refine_poses"},
      {R"({"no_such_setting": 1})", "no_such_setting"},
  };
  for (const BadSetting& bad : cases) expect_rejected(bad, splat_training_preset("compact"));
}

TEST(ConfigLimits, EveryPresetPassesItsOwnChecks) {
  // What a run writes to config.json must read back: the defaults are inside every range.
  for (const char* strategy : kSplatStrategies) {
    const SplatTrainingConfig preset = splat_training_preset(strategy);
    SplatTrainingConfig read = splat_training_preset("official");
    EXPECT_NO_THROW(from_json(to_json(preset), read)) << strategy;
    EXPECT_EQ(to_json(read), to_json(preset)) << strategy;
  }
  NerfTrainingConfig nerf;
  NerfTrainingConfig read;
  EXPECT_NO_THROW(from_json(to_json(nerf), read));
  EXPECT_EQ(to_json(read), to_json(nerf));
}

TEST(ConfigLimits, NerfSettingsOutsideTheirRangesAreRejectedNamingTheKey) {
  const BadSetting cases[] = {
      {R"({"iterations": 0})", "iterations"},
      {R"({"rays_per_batch": 1e9})", "rays_per_batch"},
      {R"({"lr_init": -1})", "lr_init"},
      {R"({"lr_final": 100})", "lr_final"},
      {R"({"occupancy_interval": 0})", "occupancy_interval"},
      {R"({"background": [0, 5, 0]})", "background"},
      {R"({"density_bias_init": 1e30})", "density_bias_init"},
      {R"({"model": {"occupancy_resolution": 1024}})", "model.occupancy_resolution"},
      {R"({"model": {"coarse_samples": 100000}})", "model.coarse_samples"},
      {R"({"model": {"fine_samples": -1}})", "model.fine_samples"},
      {R"({"model": {"fine": {"width": 1000000}}})", "model.fine.width"},
      {R"({"model": {"coarse": {"depth": 2.5}}})", "model.coarse.depth"},
      {R"({"model": {"fine": {"colour_width": 64}}})", "model.fine.colour_width"},
      {R"({"model": {"samples": 64}})", "model.samples"},
      {R"({"model": {"box_min": [0, 0, 0], "box_max": [0, 1, 1]}})", "box_min"},
      {R"({"model": {"box_max": [1e30, 1, 1]}})", "model.box_max"},
      {R"({"no_such_setting": 1})", "no_such_setting"},
  };
  for (const BadSetting& bad : cases) expect_rejected(bad, NerfTrainingConfig{});
}

}  // namespace
}  // namespace splat
