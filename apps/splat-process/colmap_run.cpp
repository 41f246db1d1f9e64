#include "apps/splat-process/colmap_run.hpp"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <sstream>

#include "apps/common/external_program.hpp"
#include "splat/core/error.hpp"
#include "splat/data/colmap_model.hpp"

namespace fs = std::filesystem;

namespace splat::process {
namespace {

constexpr const char* kNoModel =
    "COLMAP's mapper made no model: the photos share too few features (more overlap between neighbouring photos, "
    "sharper photos or more texture help)";

// Follows the log as COLMAP appends to it: the newest progress among the whole lines added
// since the last look.
class LogFollower {
 public:
  explicit LogFollower(const fs::path& log) : log_(log) {
    std::error_code ec;
    const auto size = fs::file_size(log_, ec);
    offset_ = ec ? 0 : std::streamoff(size);
  }
  std::string newest_progress() {
    std::ifstream in(log_, std::ios::binary);
    if (!in || !in.seekg(offset_)) return {};
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t end = text.rfind('\n');
    if (end == std::string::npos) return {};
    offset_ += std::streamoff(end + 1);
    std::string newest, line;
    std::istringstream lines(text.substr(0, end));
    while (std::getline(lines, line))
      if (std::string p = colmap_progress(line); !p.empty()) newest = std::move(p);
    return newest;
  }

 private:
  fs::path log_;
  std::streamoff offset_ = 0;
};

void run_stage(std::vector<std::string> arguments, const ColmapRunOptions& options, const std::string& what,
               const std::function<void(const std::string&)>& progress) {
  const fs::path log = options.work_dir / "colmap.log";
  LogFollower follower(log);
  std::string newest;
  const int status = cli::run_program(arguments, log, [&] {
    if (std::string now = follower.newest_progress(); !now.empty()) newest = std::move(now);
    progress(newest);
  });
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

// The numbers inside the brackets (or parentheses) that follow `prefix` in `line`.
std::vector<int> numbers_after(const std::string& line, const std::string& prefix) {
  std::vector<int> numbers;
  const std::size_t at = line.find(prefix);
  if (at == std::string::npos) return numbers;
  const std::size_t close = line.find_first_of("])", at + prefix.size());
  if (close == std::string::npos) return numbers;
  std::string inside = line.substr(at + prefix.size(), close - at - prefix.size());
  std::replace_if(inside.begin(), inside.end(), [](char c) { return c < '0' || c > '9'; }, ' ');
  std::istringstream in(inside);
  for (int n = 0; in >> n;) numbers.push_back(n);
  return numbers;
}

}  // namespace

std::string colmap_progress(const std::string& line) {
  if (auto n = numbers_after(line, "Processed file ["); n.size() == 2)
    return "features of " + std::to_string(n[0]) + "/" + std::to_string(n[1]) + " images";
  if (auto n = numbers_after(line, "Matching block ["); n.size() == 4)
    return std::to_string((n[0] - 1) * n[3] + n[2]) + "/" + std::to_string(n[1] * n[3]) + " blocks of pairs matched";
  if (auto n = numbers_after(line, "Matching image ["); n.size() == 2)
    return std::to_string(n[0]) + "/" + std::to_string(n[1]) + " images matched";
  if (line.find("Registering image #") != std::string::npos)
    if (auto n = numbers_after(line, "("); n.size() == 1) return std::to_string(n[0]) + " images registered";
  return {};
}

Reconstruction run_colmap(const ColmapRunOptions& options, const std::function<void(const std::string&)>& stage,
                          const std::function<void(const std::string&)>& progress) {
  const std::string database = (options.work_dir / "database.db").string();
  const std::string images = options.images_dir.string();
  const std::string threads = std::to_string(options.threads > 0 ? options.threads : -1);

  stage("extracting features");
  run_stage({"colmap", "feature_extractor", "--database_path", database, "--image_path", images,
             "--ImageReader.single_camera", options.single_camera ? "1" : "0", "--SiftExtraction.use_gpu", "0",
             "--SiftExtraction.num_threads", threads},
            options, "feature extraction", progress);

  const bool exhaustive = options.matcher == Matcher::kExhaustive;
  stage(exhaustive ? "matching every pair of images" : "matching neighbouring frames");
  run_stage({"colmap", exhaustive ? "exhaustive_matcher" : "sequential_matcher", "--database_path", database,
             "--SiftMatching.use_gpu", "0", "--SiftMatching.num_threads", threads},
            options, "matching", progress);

  stage("mapping (incremental structure from motion)");
  const fs::path models_dir = options.work_dir / "sparse";
  fs::create_directories(models_dir);
  run_stage({"colmap", "mapper", "--database_path", database, "--image_path", images, "--output_path",
             models_dir.string(), "--Mapper.num_threads", threads},
            options, "mapper", progress);

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
