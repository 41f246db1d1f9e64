// Training config files (splat-train --config), for both methods, read as the tools read them.
#include "splat/train/config_file.hpp"
#include "fuzz/fuzz_support.hpp"
#include "splat/train/nerf_trainer.hpp"
#include "splat/train/training_config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace splat;
  fuzz::read_input_as("splat_config.json", data, size, [](const auto& f) {
    SplatTrainingConfig config = splat_training_preset("compact");
    read_config_file(f, config);
  });
  return fuzz::read_input_as("nerf_config.json", data, size, [](const auto& f) {
    NerfTrainingConfig config;
    read_config_file(f, config);
  });
}
