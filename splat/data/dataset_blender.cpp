// Blender / NeRF-synthetic folders: transforms_train.json and transforms_test.json (or
// transforms_val.json), each frame an image, usually RGBA, to composite onto the background.
#include <string>
#include <vector>

#include "splat/core/error.hpp"
#include "splat/data/dataset_loading.hpp"
#include "splat/data/transforms_json.hpp"

namespace splat::dataset_detail {
namespace {

namespace fs = std::filesystem;

struct Job {
  const CameraFrame* frame;
  const fs::path* transforms;
  DatasetView* out;
};

}  // namespace

Dataset load_blender(const fs::path& folder, const DatasetOptions& options) {
  const fs::path train_file = folder / "transforms_train.json";
  // Folders without a test split commonly ship a validation split in its place.
  fs::path test_file = folder / "transforms_test.json";
  std::error_code ec;
  if (!fs::exists(test_file, ec)) test_file = folder / "transforms_val.json";
  if (!fs::exists(test_file, ec))
    throw InputError(folder / "transforms_test.json",
                     "missing, and no transforms_val.json either: a Blender dataset needs a "
                     "test (or validation) split");

  const std::vector<CameraFrame> train_frames = load_transforms(train_file);
  const std::vector<CameraFrame> test_frames = load_transforms(test_file);

  std::vector<ImageSize> sizes;
  for (const auto* frames : {&train_frames, &test_frames})
    for (const CameraFrame& frame : *frames) sizes.push_back({frame.camera.width, frame.camera.height});
  const int downscale = chosen_downscale(sizes, options);
  check_dataset_fits_in_memory(folder, sizes, downscale);

  Dataset dataset;
  dataset.downscale = downscale;
  dataset.train.resize(train_frames.size());
  dataset.test.resize(test_frames.size());
  std::vector<Job> jobs;
  jobs.reserve(train_frames.size() + test_frames.size());
  for (std::size_t i = 0; i < train_frames.size(); ++i)
    jobs.push_back({&train_frames[i], &train_file, &dataset.train[i]});
  for (std::size_t i = 0; i < test_frames.size(); ++i)
    jobs.push_back({&test_frames[i], &test_file, &dataset.test[i]});

  for_each_in_parallel(jobs.size(), [&](std::size_t i) {
    const CameraFrame& frame = *jobs[i].frame;
    jobs[i].out->name = frame.name;
    load_view(view_source(frame, *jobs[i].transforms), downscale, options.background, *jobs[i].out);
  });
  return dataset;
}

}  // namespace splat::dataset_detail
