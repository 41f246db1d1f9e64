// Checkpoints (--resume), of both trainers (the NeRF's with either preset): each loaded into a trainer of a tiny dataset of
// four 8 x 8 views, as splat-train would load it.
#include "fuzz/fuzz_support.hpp"
#include "fuzz/tiny_training_setup.hpp"
#include "splat/train/nerf_trainer.hpp"
#include "splat/train/splat_trainer.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace splat;
  fuzz::read_input_as("splat.ckpt", data, size, [](const auto& f) {
    SplatTrainer trainer(fuzz::tiny_dataset(), fuzz::tiny_splat_config());
    trainer.load_checkpoint(f);
  });
  fuzz::read_input_as("nerf.ckpt", data, size, [](const auto& f) {
    NerfTrainer trainer(fuzz::tiny_dataset(), fuzz::tiny_nerf_config());
    trainer.load_checkpoint(f);
  });
  return fuzz::read_input_as("ngp.ckpt", data, size, [](const auto& f) {
    NerfTrainer trainer(fuzz::tiny_dataset(), fuzz::tiny_ngp_config());
    trainer.load_checkpoint(f);
  });
}
