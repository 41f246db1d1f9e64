#pragma once
// A Blender-format dataset rendered from a Gaussian model with the rasterizer: exact ground
// truth for tests and demos (train on renders of a known model, compare with it).
#include <filesystem>
#include <vector>

#include "splat/core/camera.hpp"
#include "splat/gaussians/gaussian_model.hpp"

namespace splat {

// Writes folder/{train,test}/<name>.png (RGB on `background`), transforms_train.json and
// transforms_test.json. Views are named view_000, view_001, ... in each split.
void write_rendered_dataset(const GaussianModel& model, const std::vector<Camera>& train,
                            const std::vector<Camera>& test, const float background[3],
                            const std::filesystem::path& folder);

}  // namespace splat
