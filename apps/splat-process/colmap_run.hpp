#pragma once
// Structure from motion through COLMAP's command-line tools (Debian's colmap 3.8, CPU SIFT):
// features, matching, the incremental mapper, and the choice of its largest reconstruction.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace splat::process {

enum class Matcher { kExhaustive, kSequential };

struct ColmapRunOptions {
  std::filesystem::path images_dir;  // the photographs (the dataset's images/)
  std::filesystem::path work_dir;    // database, the mapper's models and colmap.log
  Matcher matcher = Matcher::kExhaustive;
  bool single_camera = true;  // one set of intrinsics for all photos (one phone, one video)
  int threads = 0;            // 0: COLMAP's default (all cores)
};

struct Reconstruction {
  std::filesystem::path sparse_dir;          // work_dir/sparse/K, the largest model
  std::vector<std::string> registered;       // image names it holds, sorted
  int models = 0;                            // how many the mapper made
};

// How far a stage has gone, from the lines COLMAP 3.8 logs as it works ("Processed file
// [12/77]", "Matching block [1/2, 2/2]", "Matching image [40/77]", "Registering image #3
// (40)"): "features of 12/77 images", "2/4 blocks of pairs matched", "40/77 images matched",
// "40 images registered"; empty for any other line.
std::string colmap_progress(const std::string& log_line);

// Runs the three stages in turn, calling `stage(name)` before each and, about four times a
// second while one runs, `progress(text)` with the newest progress its log shows
// (colmap_progress; empty before the first), with COLMAP's output appended to
// work_dir/colmap.log. ArgumentError (with the log's tail) when a stage fails or makes no
// model.
Reconstruction run_colmap(const ColmapRunOptions& options, const std::function<void(const std::string&)>& stage,
                          const std::function<void(const std::string&)>& progress);

}  // namespace splat::process
