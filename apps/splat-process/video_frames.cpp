#include "apps/splat-process/video_frames.hpp"

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "apps/common/external_program.hpp"
#include "splat/core/error.hpp"
#include "splat/core/image.hpp"
#include "splat/data/image_io.hpp"

namespace fs = std::filesystem;

namespace splat::process {
namespace {

double video_duration_seconds(const VideoFrameOptions& options) {
  const fs::path log = options.work_dir / "ffprobe.log";
  const int status = cli::run_program({"ffprobe", "-v", "error", "-show_entries", "format=duration", "-of",
                                       "default=noprint_wrappers=1:nokey=1", options.video.string()},
                                      log);
  const std::string last = cli::last_line_of_file(log);
  double seconds = 0;
  if (status != 0 || std::sscanf(last.c_str(), "%lf", &seconds) != 1 || !(seconds > 0))
    throw InputError(options.video, "ffprobe cannot read a duration from the video: " + last);
  return seconds;
}

}  // namespace

double sharpness(const Image& image) {
  if (image.width < 3 || image.height < 3) return 0;
  std::vector<double> luma(image.pixel_count());
  for (std::size_t p = 0; p < luma.size(); ++p) {
    const float* px = image.data.data() + p * std::size_t(image.channels);
    luma[p] = image.channels >= 3 ? 0.299 * px[0] + 0.587 * px[1] + 0.114 * px[2] : px[0];
  }
  double sum = 0, sum_of_squares = 0;
  std::size_t count = 0;
  for (int y = 1; y + 1 < image.height; ++y)
    for (int x = 1; x + 1 < image.width; ++x) {
      const std::size_t p = std::size_t(y) * std::size_t(image.width) + std::size_t(x);
      const double laplacian = luma[p - 1] + luma[p + 1] + luma[p - std::size_t(image.width)] +
                               luma[p + std::size_t(image.width)] - 4 * luma[p];
      sum += laplacian;
      sum_of_squares += laplacian * laplacian;
      ++count;
    }
  const double mean = sum / double(count);
  return sum_of_squares / double(count) - mean * mean;
}

int extract_sharp_frames(const VideoFrameOptions& options) {
  const double duration = video_duration_seconds(options);
  const int wanted = options.frames * options.candidates_per_frame;
  const fs::path candidates_dir = options.work_dir / "candidates";
  fs::create_directories(candidates_dir);
  std::string filter = "fps=" + std::to_string(double(wanted) / duration);
  if (options.max_side > 0) {
    const std::string side = std::to_string(options.max_side);
    filter += ",scale='if(gte(iw,ih),min(" + side + ",iw),-2)':'if(gte(iw,ih),-2,min(" + side + ",ih))'";
  }
  const fs::path log = options.work_dir / "ffmpeg.log";
  const int status = cli::run_program({"ffmpeg", "-nostdin", "-v", "error", "-i", options.video.string(), "-vf", filter,
                                       "-frames:v", std::to_string(wanted), (candidates_dir / "c_%05d.png").string()},
                                      log);
  if (status != 0) throw InputError(options.video, "ffmpeg cannot read the video: " + cli::last_line_of_file(log));
  std::vector<fs::path> candidates;
  for (const fs::directory_entry& entry : fs::directory_iterator(candidates_dir)) candidates.push_back(entry.path());
  std::sort(candidates.begin(), candidates.end());
  if (candidates.empty()) throw InputError(options.video, "ffmpeg found no video frames in it");

  const int kept = std::min<int>(options.frames, int(candidates.size()));
  fs::create_directories(options.images_dir);
  for (int k = 0; k < kept; ++k) {
    const std::size_t first = std::size_t(k) * candidates.size() / std::size_t(kept);
    const std::size_t end = std::size_t(k + 1) * candidates.size() / std::size_t(kept);
    std::size_t best = first;
    double best_sharpness = -1;
    for (std::size_t c = first; c < end; ++c) {
      const double s = sharpness(read_image(candidates[c]));
      if (s > best_sharpness) {  // ties keep the earlier frame
        best_sharpness = s;
        best = c;
      }
    }
    char name[32];
    std::snprintf(name, sizeof(name), "frame_%04d.png", k);
    fs::copy_file(candidates[best], options.images_dir / name, fs::copy_options::overwrite_existing);
  }
  fs::remove_all(candidates_dir);
  return kept;
}

}  // namespace splat::process
