#include "tests/rendered_dataset.hpp"

#include <cstdio>
#include <string>

#include "splat/core/error.hpp"
#include "splat/data/image_io.hpp"
#include "splat/data/orbit_cameras.hpp"
#include "splat/raster/rasterizer.hpp"

namespace splat {

namespace {

void write_split(const GaussianModel& model, const std::vector<Camera>& cameras,
                 const float background[3], const std::filesystem::path& folder,
                 const std::string& split) {
  std::filesystem::create_directories(folder / split);
  Rasterizer rasterizer;
  RenderResult result;
  RenderSettings settings;
  std::copy(background, background + 3, settings.background);
  std::vector<std::string> file_paths;
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof(name), "view_%03zu", i);
    rasterizer.render(model, cameras[i], settings, result);
    write_png(result.color, folder / split / (std::string(name) + ".png"));
    file_paths.push_back("./" + split + "/" + name);
  }
  write_transforms(folder / ("transforms_" + split + ".json"), cameras, file_paths);
}

}  // namespace

void write_rendered_dataset(const GaussianModel& model, const std::vector<Camera>& train,
                            const std::vector<Camera>& test, const float background[3],
                            const std::filesystem::path& folder) {
  if (train.empty() || test.empty())
    throw ArgumentError("write_rendered_dataset: need at least one train and one test camera");
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (!std::filesystem::is_directory(folder))
    throw InputError(folder, "cannot create the dataset folder");
  write_split(model, train, background, folder, "train");
  write_split(model, test, background, folder, "test");
}

}  // namespace splat
