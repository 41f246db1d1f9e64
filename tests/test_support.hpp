#pragma once
// Small helpers shared by the tests: scratch folders, random scenes, image comparison.
#include <filesystem>
#include <string>
#include <vector>

#include "splat/core/camera.hpp"
#include "splat/core/image.hpp"
#include "splat/data/dataset.hpp"
#include "splat/data/transforms_json.hpp"
#include "splat/eval/metrics.hpp"
#include "splat/gaussians/gaussian_model.hpp"

namespace splat::test {

// A fresh empty folder under the build tree for one test (removed first if present).
std::filesystem::path scratch_dir(const std::string& name);

// testdata/conformance in the repository: the official rasterizer's images and gradients of
// a real model (testdata/README.md).
std::filesystem::path conformance_dir();

// The benchmark datasets (lego400, lego400_colmap, ...) of ../shared/data beside the checkout.
// They are not part of the repository, so the tests that check them skip without them
// (SPLAT_SKIP_WITHOUT_BENCHMARK_DATA); CI has them.
std::filesystem::path benchmark_data_dir();
bool have_benchmark_data(const std::string& dataset);
#define SPLAT_SKIP_WITHOUT_BENCHMARK_DATA(dataset)                                        \
  if (!::splat::test::have_benchmark_data(dataset))                                       \
  GTEST_SKIP() << "benchmark data " << (::splat::test::benchmark_data_dir() / (dataset)) \
               << " is not beside the checkout"

// The 50k-Gaussian conformance model and its 13 test views at size x size pixels.
struct ConformanceScene {
  GaussianModel model;
  std::vector<CameraFrame> frames;
};
ConformanceScene load_conformance(int size);

// Writes `text` to `file` (for hand-made bad inputs).
void write_text(const std::filesystem::path& file, const std::string& text);

// A small untrained NeRF written to `file`: it still draws a definite picture (its random
// networks' colours), quickly.
void write_tiny_nerf(const std::filesystem::path& file);

// A camera at `distance` on the -z axis looking at the origin (OpenCV axes), square image.
// Twenty training views round `target` (two orbits of ten, at elevations 0.15 and 0.6 rad,
// `radius` away), grey `size`² images, with the frame showing only the background
// (`transparent`) or none of it.
Dataset orbit_dataset(const glm::vec3& target, float radius, float fov_x, int size, bool transparent);

Camera looking_at_origin(int width, int height, float distance = 4.0f, float fov_x = 0.8f);

// `count` Gaussians with random parameters in a cube of half-size `extent` around the
// origin, SH degree `sh_degree`; scales in [min_scale, max_scale] (log-uniform).
GaussianModel random_model(int count, int sh_degree, unsigned seed, float extent = 1.0f,
                           float min_scale = 0.02f, float max_scale = 0.3f);

}  // namespace splat::test
