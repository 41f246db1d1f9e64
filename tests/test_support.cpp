#include "tests/test_support.hpp"

#include <cmath>
#include <fstream>
#include <random>

#include "splat/core/error.hpp"
#include "splat/data/orbit_cameras.hpp"
#include "splat/gaussians/ply_io.hpp"
#include "splat/nerf/nerf_file.hpp"

namespace splat::test {

std::filesystem::path scratch_dir(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(SPLAT_TEST_TMP) / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

std::filesystem::path conformance_dir() { return std::filesystem::path(SPLAT_TEST_DATA_DIR) / "conformance"; }

std::filesystem::path benchmark_data_dir() { return std::filesystem::path(SPLAT_BENCHMARK_DATA_DIR); }

bool have_benchmark_data(const std::string& dataset) {
  return std::filesystem::is_directory(benchmark_data_dir() / dataset);
}

ConformanceScene load_conformance(int size) {
  const auto dir = conformance_dir();
  TransformsOptions options;
  options.width = options.height = size;
  return {read_ply(dir / "lego_subset50k.ply"), load_transforms(dir / "transforms_test.json", options)};
}

void write_text(const std::filesystem::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary);
  out << text;
}

Camera looking_at_origin(int width, int height, float distance, float fov_x) {
  Camera cam;
  cam.width = width;
  cam.height = height;
  cam.fx = cam.fy = 0.5f * float(width) / std::tan(0.5f * fov_x);
  cam.cx = 0.5f * float(width);
  cam.cy = 0.5f * float(height);
  cam.camera_from_world_translation = glm::vec3(0, 0, distance);  // identity rotation
  return cam;
}

GaussianModel random_model(int count, int sh_degree, unsigned seed, float extent,
                           float min_scale, float max_scale) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::normal_distribution<float> n(0.0f, 1.0f);
  GaussianModel m;
  m.sh_degree = sh_degree;
  m.resize(count);
  const float log_lo = std::log(min_scale), log_hi = std::log(max_scale);
  for (int i = 0; i < count; ++i) {
    for (int a = 0; a < 3; ++a) {
      m.means[i * 3 + a] = extent * u(rng);
      m.log_scales[i * 3 + a] = log_lo + (log_hi - log_lo) * 0.5f * (u(rng) + 1.0f);
    }
    for (int a = 0; a < 4; ++a) m.quats[i * 4 + a] = n(rng);
    m.opacity_logits[i] = 2.0f * n(rng);
    for (int k = 0; k < m.sh_coefficients() * 3; ++k)
      m.sh[std::size_t(i) * m.sh_coefficients() * 3 + k] = (k < 3 ? 1.0f : 0.3f) * n(rng);
  }
  return m;
}

Dataset orbit_dataset(const glm::vec3& target, float radius, float fov_x, int size, bool transparent) {
  Dataset dataset;
  for (float elevation : {0.15f, 0.6f}) {
    OrbitRig rig;
    rig.count = 10;
    rig.radius = radius;
    rig.elevation_radians = elevation;
    rig.fov_x_radians = fov_x;
    rig.width = rig.height = size;
    rig.target = target;
    for (const Camera& camera : orbit_cameras(rig)) {
      DatasetView view;
      view.camera = camera;
      view.image = Image(size, size, 3, 0.5f);
      view.frame_background_share = transparent ? 1.0f : 0.0f;
      dataset.train.push_back(view);
    }
  }
  return dataset;
}

void write_tiny_nerf(const std::filesystem::path& file) {
  NerfSettings settings;
  settings.coarse = frequency_mlp_config(4, 2, 2, 16, -1, 8);
  settings.fine = settings.coarse;
  settings.coarse_samples = 16;
  settings.fine_samples = 8;
  write_nerf(NerfModel(settings, 5), file);
}

}  // namespace splat::test
