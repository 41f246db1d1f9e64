// splat-process: a folder of photographs, or a video, to a COLMAP dataset folder that
// splat-train --data reads (docs/DESIGN.md §5 "splat-process"): photos imported at a size the
// trainer handles (or sharp frames taken from the video by ffmpeg), then COLMAP's features,
// matching and mapper, and its largest reconstruction kept as sparse/0.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "apps/common/arg_parser.hpp"
#include "apps/common/external_program.hpp"
#include "apps/common/run_main.hpp"
#include "apps/splat-process/colmap_run.hpp"
#include "apps/splat-process/photo_import.hpp"
#include "apps/splat-process/video_frames.hpp"
#include "splat/core/error.hpp"
#include "splat/data/colmap_model.hpp"

namespace fs = std::filesystem;

namespace {

constexpr const char* kUsage = R"(usage: splat-process --images DIR --out DATASET [options]
       splat-process --video FILE --out DATASET [--frames N] [options]

Makes a dataset folder that splat-train --data reads from photographs with no poses: the
photos (or sharp, evenly spread frames of the video, taken by ffmpeg) go to DATASET/images,
COLMAP (its command-line tools, on the CPU) finds the cameras and a sparse point cloud, and its
largest reconstruction becomes DATASET/sparse/0. COLMAP's log and database stay in
DATASET/colmap/. The camera model is COLMAP's choice (SIMPLE_RADIAL); splat-train undistorts.

  --images DIR          a folder of .jpg/.jpeg/.png photos of one scene
  --video FILE          a video of one scene (anything ffmpeg reads)
  --out DATASET         the dataset folder to make (must not exist, or be empty)
  --frames N            frames to take from the video (default 100)
  --max-size PX         photos and frames larger than PX on their longest side are
                        downscaled to it on the way in (default 1600, as the official
                        trainer does; 0 keeps them as they are)
  --matcher NAME        exhaustive (every pair: the default for photos) or sequential
                        (neighbouring frames: the default for a video)
  --camera-per-image    intrinsics of their own for every photo (default: one camera for
                        all, as from one phone or one video)
  --threads N           COLMAP's threads (default: all cores)

Needs COLMAP (sudo apt-get install colmap) and, for a video, ffmpeg (sudo apt-get install
ffmpeg); scripts/install-deps.sh installs both.
)";

constexpr int kMinimumRegistered = 3;

void require_program(const std::string& name, const std::string& package) {
  if (!splat::cli::program_on_path(name))
    throw splat::ArgumentError(name + " not found on PATH: install it with `sudo apt-get install " + package +
                               "` (Debian/Ubuntu; scripts/install-deps.sh installs it)");
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Seconds since `start`, and `start` moved to now.
double lap(std::chrono::steady_clock::time_point& start) {
  const double seconds = seconds_since(start);
  start = std::chrono::steady_clock::now();
  return seconds;
}

std::string seconds_text(double seconds) { return std::to_string(std::lround(seconds)) + " s"; }

// COLMAP's progress within a stage, with the stage's seconds so far: on a terminal one line
// redrawn in place as either changes; otherwise (a log) a line when the progress has changed
// and kPlainInterval has passed since the last line.
class StageProgress {
 public:
  explicit StageProgress(bool terminal) : terminal_(terminal), last_line_(std::chrono::steady_clock::now()) {}
  void show(const std::string& progress, double seconds) {
    const std::string text = "  " + (progress.empty() ? "" : progress + ", ") + seconds_text(seconds);
    if (text == drawn_text_) return;
    if (terminal_) {
      std::printf("\r%-*s", int(std::max(text.size(), drawn_text_.size())), text.c_str());
      drawn_text_ = text;
    } else {
      if (progress.empty() || progress == printed_progress_ || seconds_since(last_line_) < kPlainInterval) return;
      std::printf("%s\n", text.c_str());
      printed_progress_ = progress;
      last_line_ = std::chrono::steady_clock::now();
    }
    std::fflush(stdout);
  }
  // The stage's closing line, over the redrawn one.
  void end_stage(const std::string& text) {
    std::printf(drawn_text_.empty() ? "%-*s\n" : "\r%-*s\n", int(std::max(text.size(), drawn_text_.size())),
                text.c_str());
    drawn_text_.clear();
    printed_progress_.clear();
    last_line_ = std::chrono::steady_clock::now();
  }

 private:
  static constexpr double kPlainInterval = 5;
  bool terminal_;
  std::string drawn_text_;  // the line redrawn in place on a terminal (empty: none)
  std::string printed_progress_;
  std::chrono::steady_clock::time_point last_line_;
};

std::string joined(const std::vector<std::string>& names, std::size_t most) {
  std::string text;
  for (std::size_t i = 0; i < names.size() && i < most; ++i) text += (i ? ", " : "") + names[i];
  if (names.size() > most) text += " and " + std::to_string(names.size() - most) + " more";
  return text;
}

// Copies the chosen model's files (binary or text) into `sparse0`.
void keep_model(const fs::path& model, const fs::path& sparse0) {
  fs::create_directories(sparse0);
  for (const fs::directory_entry& entry : fs::directory_iterator(model))
    if (entry.is_regular_file()) fs::copy_file(entry.path(), sparse0 / entry.path().filename());
}

}  // namespace

int main(int argc, char** argv) {
  return splat::cli::run_main([&] {
    splat::cli::ArgParser args(argc, argv, {"images", "video", "out", "frames", "max-size", "matcher", "threads"},
                               {"help", "camera-per-image"});
    if (args.has("help")) {
      std::fputs(kUsage, stdout);
      return 0;
    }
    args.expect_no_positionals();
    const auto images = args.value("images"), video = args.value("video");
    if (images.has_value() == video.has_value())
      throw splat::ArgumentError("give --images DIR or --video FILE (one of them; see --help)");
    const fs::path out = args.required("out");
    if (args.has("frames") && !video) throw splat::ArgumentError("--frames is for --video");
    const int frames = args.integer("frames", {1, 10000}).value_or(100);
    const int max_size = args.integer("max-size", {0, 65536}).value_or(1600);
    if (max_size > 0 && max_size < 64) throw splat::ArgumentError("option --max-size must be 0 (keep) or 64 to 65536 pixels, got '" + std::to_string(max_size) + "'");
    splat::process::ColmapRunOptions colmap;
    colmap.matcher = video ? splat::process::Matcher::kSequential : splat::process::Matcher::kExhaustive;
    if (auto matcher = args.value("matcher")) {
      if (*matcher == "exhaustive") colmap.matcher = splat::process::Matcher::kExhaustive;
      else if (*matcher == "sequential") colmap.matcher = splat::process::Matcher::kSequential;
      else throw splat::ArgumentError("--matcher must be exhaustive or sequential, not '" + *matcher + "'");
    }
    colmap.single_camera = !args.has("camera-per-image");
    colmap.threads = args.integer("threads", splat::cli::kThreadsRange).value_or(0);

    // Inputs and tools first: nothing is made before they are known good.
    std::vector<fs::path> photos;
    if (images) {
      photos = splat::process::list_images(*images);
      if (photos.size() < std::size_t(kMinimumRegistered))
        throw splat::InputError(*images, std::to_string(photos.size()) + " image" + (photos.size() == 1 ? "" : "s") +
                                             "; structure from motion needs 3 or more (50-150 for an object)");
    } else {
      std::error_code ec;
      if (!fs::is_regular_file(*video, ec)) throw splat::InputError(*video, "no such video file");
      require_program("ffmpeg", "ffmpeg");
      require_program("ffprobe", "ffmpeg");
    }
    require_program("colmap", "colmap");
    std::error_code ec;
    if (fs::exists(out, ec) && !(fs::is_directory(out, ec) && fs::is_empty(out, ec)))
      throw splat::InputError(out, "already exists and is not empty (choose another --out, or remove it)");

    // Everything is made in a sibling folder and renamed into place at the end, so a failure
    // leaves no half-made dataset.
    const fs::path partial = out.string() + ".partial";
    fs::remove_all(partial);
    fs::create_directories(partial / "colmap");
    colmap.images_dir = partial / "images";
    colmap.work_dir = partial / "colmap";
    try {
      auto clock = std::chrono::steady_clock::now();
      const auto start = clock;
      std::size_t input_count = 0;
      if (images) {
        std::printf("importing %zu photos from %s\n", photos.size(), images->c_str());
        std::fflush(stdout);
        const splat::process::ImportedPhotos imported =
            splat::process::import_photos(photos, colmap.images_dir, max_size);
        if (imported.scale < 1.0)
          std::printf("  downscaled by %.3f: the largest, %d x %d, to %ld x %ld (--max-size %d; 0 keeps them)\n",
                      imported.scale, imported.largest_width, imported.largest_height,
                      std::lround(imported.largest_width * imported.scale),
                      std::lround(imported.largest_height * imported.scale), max_size);
        else
          std::printf("  copied as they are (the largest is %d x %d, within --max-size %d)\n", imported.largest_width,
                      imported.largest_height, max_size);
        input_count = photos.size();
      } else {
        std::printf("taking %d sharp frames from %s\n", frames, video->c_str());
        std::fflush(stdout);
        splat::process::VideoFrameOptions options;
        options.video = *video;
        options.frames = frames;
        options.max_side = max_size;
        options.work_dir = colmap.work_dir;
        options.images_dir = colmap.images_dir;
        input_count = std::size_t(splat::process::extract_sharp_frames(options));
        std::printf("  %zu frames (the sharpest of %d candidates each)\n", input_count, options.candidates_per_frame);
      }
      std::printf("  %.0f s\n", lap(clock));

      int step = 0;
      StageProgress progress(::isatty(STDOUT_FILENO) == 1);
      const splat::process::Reconstruction model = splat::process::run_colmap(
          colmap,
          [&](const std::string& stage) {
            if (step > 0) progress.end_stage("  " + seconds_text(lap(clock)));
            std::printf("COLMAP %d/3: %s (log: %s)\n", ++step, stage.c_str(), (colmap.work_dir / "colmap.log").c_str());
            std::fflush(stdout);
          },
          [&](const std::string& text) { progress.show(text, seconds_since(clock)); });
      progress.end_stage("  " + seconds_text(lap(clock)));

      // Which inputs the model lacks, by name.
      std::vector<std::string> unregistered;
      for (const fs::directory_entry& entry : fs::directory_iterator(colmap.images_dir)) {
        const std::string name = entry.path().filename().string();
        if (!std::binary_search(model.registered.begin(), model.registered.end(), name)) unregistered.push_back(name);
      }
      std::sort(unregistered.begin(), unregistered.end());
      const std::size_t registered = model.registered.size();
      if (registered < std::size_t(kMinimumRegistered) || 2 * registered < input_count)
        throw splat::ArgumentError("too few images registered: " + std::to_string(registered) + " of " +
                                   std::to_string(input_count) + " (at least half, and 3, are needed); not placed: " +
                                   joined(unregistered, 30) +
                                   ". More overlap between neighbouring photos, or sharper ones, help");
      if (!unregistered.empty())
        std::printf("note: %zu of %zu images were not placed and are left out of the dataset's poses: %s\n",
                    unregistered.size(), input_count, joined(unregistered, 20).c_str());
      if (model.models > 1)
        std::printf("note: COLMAP made %d separate models; the largest is kept\n", model.models);
      keep_model(model.sparse_dir, partial / "sparse" / "0");
      const splat::ColmapModel kept = splat::read_colmap_model(partial / "sparse" / "0");
      fs::remove_all(out);  // an empty folder, checked above
      fs::rename(partial, out);
      std::printf("%s: %zu of %zu images registered, %zu camera(s) (%s), %zu points, in %.0f s\n", out.c_str(),
                  registered, input_count, kept.cameras.size(),
                  splat::colmap_model_name(int(kept.cameras.front().model)).c_str(), kept.point_positions.size() / 3,
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      std::printf("next: splat-train --data %s --out MODEL_DIR\n", out.c_str());
    } catch (...) {
      fs::remove_all(partial, ec);
      throw;
    }
    return 0;
  });
}
