#include "apps/splat-process/colmap_run.hpp"

#include <algorithm>

#include "apps/common/external_program.hpp"
#include "splat/core/error.hpp"
#include "splat/data/colmap_model.hpp"

namespace fs = std::filesystem;

namespace splat::process {
namespace {

constexpr const char* kNoModel =
    "COLMAP's mapper made no model: the photos share too few features (more overlap between neighbouring photos, "
    "sharper photos or more texture help)";

void run_stage(std::vector<std::string> arguments, const ColmapRunOptions& options, const std::string& what) {
  const fs::path log = options.work_dir / "colmap.log";
  const int status = cli::run_program(arguments, log);
  if (status != 0 && cli::last_line_of_file(log).find("failed to create sparse model") != std::string::npos)
    throw ArgumentError(kNoModel);
  if (status != 0)
    throw ArgumentError("COLMAP's " + what + " failed (exit status " + std::to_string(status) +
                        "); its last words: " + cli::last_line_of_file(log));
}

std::vector<std::string> registered_images(const fs::path& sparse_dir) {
  const fs::path file = fs::exists(sparse_dir / "images.bin") ? sparse_dir / "images.bin" : sparse_dir / "images.txt";
  std::vector<std::string> names;
  for (const ColmapImage& image : read_colmap_images(file)) names.push_back(image.name);
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

Reconstruction run_colmap(const ColmapRunOptions& options, const std::function<void(const std::string&)>& stage) {
  const std::string database = (options.work_dir / "database.db").string();
  const std::string images = options.images_dir.string();
  const std::string threads = std::to_string(options.threads > 0 ? options.threads : -1);

  stage("extracting features");
  run_stage({"colmap", "feature_extractor", "--database_path", database, "--image_path", images,
             "--ImageReader.single_camera", options.single_camera ? "1" : "0", "--SiftExtraction.use_gpu", "0",
             "--SiftExtraction.num_threads", threads},
            options, "feature extraction");

  const bool exhaustive = options.matcher == Matcher::kExhaustive;
  stage(exhaustive ? "matching every pair of images" : "matching neighbouring frames");
  run_stage({"colmap", exhaustive ? "exhaustive_matcher" : "sequential_matcher", "--database_path", database,
             "--SiftMatching.use_gpu", "0", "--SiftMatching.num_threads", threads},
            options, "matching");

  stage("mapping (incremental structure from motion)");
  const fs::path models_dir = options.work_dir / "sparse";
  fs::create_directories(models_dir);
  run_stage({"colmap", "mapper", "--database_path", database, "--image_path", images, "--output_path",
             models_dir.string(), "--Mapper.num_threads", threads},
            options, "mapper");

  Reconstruction largest;
  std::vector<fs::path> models;
  for (const fs::directory_entry& entry : fs::directory_iterator(models_dir))
    if (entry.is_directory()) models.push_back(entry.path());
  std::sort(models.begin(), models.end());
  for (const fs::path& model : models) {
    std::vector<std::string> names = registered_images(model);
    if (names.size() > largest.registered.size()) largest = {model, std::move(names), 0};
  }
  largest.models = int(models.size());
  if (largest.registered.empty())
    throw ArgumentError(kNoModel);
  return largest;
}

}  // namespace splat::process
