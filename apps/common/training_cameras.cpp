#include "apps/common/training_cameras.hpp"

#include <cstdio>

#include "splat/train/trainer_adapter.hpp"

namespace splat::cli {

std::optional<std::filesystem::path> announced_training_cameras(const std::filesystem::path& folder) {
  std::optional<std::filesystem::path> file = training_cameras_in(folder);
  if (file) std::printf("cameras: %s, the views the model trained on (--cameras to choose others)\n", file->c_str());
  return file;
}

}  // namespace splat::cli
