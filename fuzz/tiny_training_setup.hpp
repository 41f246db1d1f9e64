#pragma once
// The tiny dataset and trainer settings the checkpoint target loads checkpoints into, shared
// with make_seed_corpus, which writes seed checkpoints that fit them (a checkpoint for another
// dataset is refused at its first check, and the fuzzer would rarely get past it).
#include <string>

#include "splat/data/dataset.hpp"
#include "splat/train/nerf_trainer.hpp"
#include "splat/train/splat_trainer.hpp"

namespace splat::fuzz {

// Four 8 x 8 grey views (three to train on) looking down the z axis from z = 4.
inline const Dataset& tiny_dataset() {
  static const Dataset dataset = [] {
    Dataset d;
    for (int k = 0; k < 4; ++k) {
      DatasetView view;
      view.name = "v" + std::to_string(k);
      view.camera.width = view.camera.height = 8;
      view.camera.fx = view.camera.fy = 8;
      view.camera.cx = view.camera.cy = 4;
      view.camera.camera_from_world_translation = glm::vec3(0.1f * float(k), 0, 4);
      view.image = Image(8, 8, 3, 0.5f);
      (k == 3 ? d.test : d.train).push_back(view);
    }
    d.scene_extent = 4.4f;
    return d;
  }();
  return dataset;
}

inline SplatTrainingConfig tiny_splat_config() {
  SplatTrainingConfig config = splat_training_preset("compact");
  config.random_init_points = 64;
  return config;
}

inline NerfTrainingConfig tiny_nerf_config() {
  NerfTrainingConfig config;
  const NerfMlpConfig tiny = frequency_mlp_config(2, 1, 1, 8, -1, 8);
  config.model.coarse = config.model.fine = tiny;
  config.model.occupancy_resolution = 8;
  return config;
}

// The NGP preset with hash tables of a few hundred values.
inline NerfTrainingConfig tiny_ngp_config() {
  NerfTrainingConfig config = nerf_training_preset("ngp");
  for (NerfMlpConfig* network : {&config.model.coarse, &config.model.fine}) {
    network->width = network->color_width = 8;
    network->direction_frequencies = 1;
    network->hash = {.levels = 2, .features = 2, .table_log2 = 6, .base_resolution = 2, .max_resolution = 8};
  }
  config.model.coarse_samples = config.model.fine_samples = 4;
  config.model.occupancy_resolution = 8;
  config.rays_per_batch = 64;
  return config;
}

}  // namespace splat::fuzz
