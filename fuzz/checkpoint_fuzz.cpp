// Checkpoints (--resume), of both trainers: each loaded into a trainer of a tiny dataset of
// four 8 x 8 views, as splat-train would load it.
#include "fuzz_support.hpp"
#include "splat/train/nerf_trainer.hpp"
#include "splat/train/splat_trainer.hpp"

namespace {

const splat::Dataset& tiny_dataset() {
  static const splat::Dataset dataset = [] {
    splat::Dataset d;
    for (int k = 0; k < 4; ++k) {
      splat::DatasetView view;
      view.name = "v" + std::to_string(k);
      view.camera.width = view.camera.height = 8;
      view.camera.fx = view.camera.fy = 8;
      view.camera.cx = view.camera.cy = 4;
      view.camera.camera_from_world_translation = glm::vec3(0.1f * float(k), 0, 4);
      view.image = splat::Image(8, 8, 3, 0.5f);
      (k == 3 ? d.test : d.train).push_back(view);
    }
    d.scene_extent = 4.4f;
    return d;
  }();
  return dataset;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace splat;
  fuzz::read_input_as("splat.ckpt", data, size, [](const auto& f) {
    SplatTrainingConfig config = splat_training_preset("compact");
    config.random_init_points = 64;
    SplatTrainer trainer(tiny_dataset(), config);
    trainer.load_checkpoint(f);
  });
  return fuzz::read_input_as("nerf.ckpt", data, size, [](const auto& f) {
    NerfTrainingConfig config;
    config.model.coarse = {2, 1, 1, 8, -1, 8, DensityActivation::kSoftplus};
    config.model.fine = {2, 1, 1, 8, -1, 8, DensityActivation::kSoftplus};
    config.model.occupancy_resolution = 8;
    NerfTrainer trainer(tiny_dataset(), config);
    trainer.load_checkpoint(f);
  });
}
