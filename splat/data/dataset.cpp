#include "splat/data/dataset.hpp"

#include <tbb/parallel_for.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>

#include "splat/core/error.hpp"
#include "splat/core/random.hpp"
#include "splat/data/dataset_loading.hpp"
#include "splat/data/image_io.hpp"
#include "splat/data/resample.hpp"
#include "splat/data/undistort.hpp"

namespace splat {
namespace dataset_detail {

namespace fs = std::filesystem;

namespace {

double dataset_bytes(const std::vector<ImageSize>& sizes, int downscale) {
  double bytes = 0;
  for (const ImageSize& s : sizes) bytes += double(s.width / downscale) * double(s.height / downscale) * 3 * sizeof(float);
  return bytes;
}

std::string gigabytes(double bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f GB", bytes / 1e9);
  return text;
}

}  // namespace

void check_dataset_fits_in_memory(const fs::path& source, const std::vector<ImageSize>& sizes, int downscale) {
  const double memory = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE));
  if (!(memory > 0)) return;  // unknown: nothing to compare with
  const double bytes = dataset_bytes(sizes, downscale);
  if (bytes <= memory / 2) return;
  int fits = downscale;
  while (fits < 64 && dataset_bytes(sizes, fits) > memory / 2) ++fits;
  throw InputError(source, "its " + std::to_string(sizes.size()) + " images take " + gigabytes(bytes) +
                               " in memory as float RGB at this size, more than half of this machine's " +
                               gigabytes(memory) + "; train at a smaller size (--downscale " +
                               std::to_string(fits) + ": " + gigabytes(dataset_bytes(sizes, fits)) + ")");
}

int chosen_downscale(const std::vector<ImageSize>& sizes, const DatasetOptions& options) {
  if (options.max_width <= 0 || options.downscale != 1) return options.downscale;
  int widest = 0;
  for (const ImageSize& size : sizes) widest = std::max(widest, size.width);
  return std::max(1, (widest + options.max_width - 1) / options.max_width);
}

int read_reduction(int width, int height, int downscale) {
  return std::size_t(width) * std::size_t(height) > kMaxImagePixels && downscale > 1 ? downscale : 1;
}

Camera reduced_camera(const Camera& camera, int reduction) {
  if (reduction == 1) return camera;
  return camera.resized(camera.width / reduction, camera.height / reduction);
}

// The image composited onto `background`; `alpha` gets its opacity where the file has an alpha
// channel that is below 1 somewhere, and is left empty otherwise.
Image read_rgb(const fs::path& file, int width, int height, int reduction, const std::string& size_source,
               const float background[3], Image& alpha) {
  std::error_code ec;
  if (!fs::exists(file, ec)) throw InputError(file, "image file does not exist");
  Image image;
  int stored_width = 0, stored_height = 0;
  if (reduction == 1) {
    if (std::size_t(width) * std::size_t(height) > kMaxImagePixels) {
      const ImageInfo stored = read_image_stored_size(file);
      if (stored.width == width && stored.height == height)
        throw InputError(file, "image is " + std::to_string(width) + " x " + std::to_string(height) +
                                   ", beyond the " + std::to_string(kMaxImagePixels) +
                                   "-pixel limit: train it with --downscale 2 or more (it is then read at that "
                                   "size)");
    }
    image = read_image(file);
    stored_width = image.width, stored_height = image.height;
  } else {
    const ImageInfo stored = read_image_stored_size(file);
    stored_width = stored.width, stored_height = stored.height;
    if (stored_width == width && stored_height == height) image = read_image_reduced(file, reduction);
  }
  if (stored_width != width || stored_height != height)
    throw InputError(file, "image is " + std::to_string(stored_width) + " x " +
                               std::to_string(stored_height) + " but " + size_source +
                               " gives its camera " + std::to_string(width) + " x " +
                               std::to_string(height));
  if (image.channels == 3) return image;
  if (image.channels != 4)
    throw InputError(file, "expected an RGB or RGBA image, not " +
                               std::to_string(image.channels) + " channels");
  Image opacity(image.width, image.height, 1);
  bool transparent = false;
  for (std::size_t p = 0; p < opacity.pixel_count(); ++p) {
    opacity.data[p] = image.data[4 * p + 3];
    transparent = transparent || opacity.data[p] < 1.0f;
  }
  if (transparent) alpha = std::move(opacity);
  return composite_onto(image, background);
}

void downscale_view(DatasetView& view, int downscale, const fs::path& file) {
  if (downscale == 1) return;
  const int width = view.image.width / downscale, height = view.image.height / downscale;
  if (width < 1 || height < 1)
    throw InputError(file, "image is " + std::to_string(view.image.width) + " x " +
                               std::to_string(view.image.height) +
                               ", too small to downscale by " + std::to_string(downscale));
  view.image = resample_area(view.image, width, height);
  if (!view.mask.empty()) view.mask = resample_area(view.mask, width, height);
  if (!view.alpha.empty()) view.alpha = resample_area(view.alpha, width, height);
  view.camera = view.camera.resized(width, height);
}

namespace {

// A mask image's first channel as weights in [0, 1] (nerfstudio: 0 leaves the pixel out),
// at 1/`reduction` of the photo's `width` x `height`, which it must match.
Image read_mask(const fs::path& file, int width, int height, int reduction) {
  std::error_code ec;
  if (!fs::exists(file, ec)) throw InputError(file, "mask image does not exist");
  const ImageInfo stored = read_image_stored_size(file);
  if (stored.width != width || stored.height != height)
    throw InputError(file, "mask is " + std::to_string(stored.width) + " x " + std::to_string(stored.height) +
                               " but its photo is " + std::to_string(width) + " x " + std::to_string(height));
  const Image image = reduction == 1 ? read_image(file) : read_image_reduced(file, reduction);
  Image mask(image.width, image.height, 1);
  for (std::size_t p = 0; p < mask.pixel_count(); ++p) mask.data[p] = image.data[p * std::size_t(image.channels)];
  return mask;
}

// A mask or opacity as the photo's undistortion sees it: the same resampling, one channel
// carried as three; nothing outside the photo counts.
Image undistorted_channel(const Image& mask, const Camera& pinhole, const LensDistortion& distortion) {
  Image rgb(mask.width, mask.height, 3);
  for (std::size_t p = 0; p < mask.pixel_count(); ++p)
    for (int c = 0; c < 3; ++c) rgb.data[3 * p + std::size_t(c)] = mask.data[p];
  const float outside[3] = {0, 0, 0};
  const Image undistorted = undistort_image(rgb, pinhole, distortion, outside);
  Image out(mask.width, mask.height, 1);
  for (std::size_t p = 0; p < out.pixel_count(); ++p) out.data[p] = undistorted.data[3 * p];
  return out;
}

}  // namespace

Dataset split_by_holdout(std::vector<DatasetView> views, const DatasetOptions& options, const fs::path& source) {
  constexpr int kTestEvery = 8;
  const std::size_t every = std::size_t(options.holdout_every.value_or(kTestEvery));
  Dataset dataset;
  for (std::size_t i = 0; i < views.size(); ++i)
    (every > 0 && i % every == 0 ? dataset.test : dataset.train).push_back(std::move(views[i]));
  if (dataset.train.empty())
    throw InputError(source, "only " + std::to_string(views.size()) + " image(s): with one in " +
                                 std::to_string(every) + " held out for testing none is left to train on");
  return dataset;
}

ViewSource view_source(const CameraFrame& frame, const fs::path& transforms) {
  return {frame.image_path, frame.mask_path, frame.camera, frame.distortion, std::nullopt,
          "the camera in " + transforms.string()};
}

void load_view(const ViewSource& source, int downscale, const float background[3], DatasetView& view) {
  const int width = source.camera.width, height = source.camera.height;
  const int reduction = read_reduction(width, height, downscale);
  view.camera = reduced_camera(source.camera, reduction);
  view.image = read_rgb(source.image, width, height, reduction, source.size_source, background, view.alpha);
  if (!source.mask.empty()) view.mask = read_mask(source.mask, width, height, reduction);
  if (!source.distortion.is_identity()) {  // the photo through a pinhole, cut to its cover
    PixelRect covered;
    if (source.covered) {
      covered = *source.covered;
    } else {
      covered = covered_region(view.camera, source.distortion);
      if (covered.width < view.camera.width / 2 || covered.height < view.camera.height / 2)
        throw InputError(source.image, "its camera's distortion leaves only " + std::to_string(covered.width) +
                                           " x " + std::to_string(covered.height) + " of the " +
                                           std::to_string(view.camera.width) + " x " +
                                           std::to_string(view.camera.height) + " image covered");
    }
    view.image = crop_image(undistort_image(view.image, view.camera, source.distortion, background), covered);
    if (!view.mask.empty())
      view.mask = crop_image(undistorted_channel(view.mask, view.camera, source.distortion), covered);
    if (!view.alpha.empty())
      view.alpha = crop_image(undistorted_channel(view.alpha, view.camera, source.distortion), covered);
    view.camera = crop_camera(view.camera, covered);
  }
  downscale_view(view, downscale / reduction, source.image);
}

void for_each_in_parallel(std::size_t count, const std::function<void(std::size_t)>& job) {
  std::vector<std::exception_ptr> errors(count);
  tbb::parallel_for(std::size_t(0), count, [&](std::size_t i) {
    try {
      job(i);
    } catch (...) {
      errors[i] = std::current_exception();
    }
  });
  for (const std::exception_ptr& error : errors)
    if (error) std::rethrow_exception(error);
}

float scene_extent(const std::vector<DatasetView>& train) {
  if (train.empty()) return 1.0f;
  glm::dvec3 mean(0.0);
  for (const DatasetView& view : train) mean += glm::dvec3(view.camera.center_in_world());
  mean /= double(train.size());
  double largest = 0;
  for (const DatasetView& view : train)
    largest = std::max(largest, glm::length(glm::dvec3(view.camera.center_in_world()) - mean));
  // One camera, or all at one spot (a tripod panorama), has no spread to scale by; the
  // official trainer would divide learning rates down to zero there.
  if (!(largest > 0)) return 1.0f;
  return float(1.1 * largest);
}

}  // namespace dataset_detail

namespace {

namespace fs = std::filesystem;

bool has_cameras_file(const fs::path& dir) {
  std::error_code ec;
  return fs::is_regular_file(dir / "cameras.bin", ec) || fs::is_regular_file(dir / "cameras.txt", ec);
}

}  // namespace

Dataset load_dataset(const fs::path& folder, const DatasetOptions& options) {
  if (options.downscale < 1)
    throw ArgumentError("downscale must be 1 or more, not " + std::to_string(options.downscale));
  if (options.holdout_every && *options.holdout_every < 0)
    throw ArgumentError("holding out every K-th view needs K = 0 (none) or more, not " +
                        std::to_string(*options.holdout_every));
  if (options.train_views < 0)
    throw ArgumentError("the number of training views must be 1 or more, not " + std::to_string(options.train_views));
  std::error_code ec;
  if (!fs::exists(folder, ec)) throw InputError(folder, "dataset folder does not exist");
  if (!fs::is_directory(folder, ec)) throw InputError(folder, "is not a folder");

  Dataset dataset;
  if (fs::exists(folder / "transforms_train.json", ec)) {
    if (options.holdout_every)
      throw InputError(folder, "a Blender dataset's test views are those of its transforms_test.json; "
                               "holding out every K-th view is for COLMAP data");
    dataset = dataset_detail::load_blender(folder, options);
  } else if (fs::exists(folder / "transforms.json", ec)) {
    dataset = dataset_detail::load_nerfstudio(folder, options);
  } else if (fs::is_directory(folder / "sparse" / "0", ec)) {
    dataset = dataset_detail::load_colmap(folder, folder / "sparse" / "0", options);
  } else if (has_cameras_file(folder / "sparse")) {
    dataset = dataset_detail::load_colmap(folder, folder / "sparse", options);
  } else {
    throw InputError(folder,
                     "not a dataset folder: expected transforms_train.json (Blender / "
                     "NeRF-synthetic), transforms.json (nerfstudio) or sparse/0/ with cameras, images "
                     "and points3D (COLMAP)");
  }
  dataset.scene_extent = dataset_detail::scene_extent(dataset.train);
  if (std::size_t(std::max(0, options.train_views)) > dataset.train.size())
    throw InputError(folder, "--train-views " + std::to_string(options.train_views) + " asks for more views than the " +
                                 std::to_string(dataset.train.size()) + " training views the dataset has");
  if (options.train_views > 0) keep_training_views(dataset, options.train_views);
  for (std::vector<DatasetView>* views : {&dataset.train, &dataset.test})
    for (DatasetView& view : *views) view.frame_background_share = frame_background_share(view.image, options.background);
  return dataset;
}

void keep_training_views(Dataset& dataset, int count) {
  if (count < 1) throw ArgumentError("at least one training view must be kept");
  const std::size_t n = dataset.train.size();
  if (std::size_t(count) >= n) return;
  std::vector<DatasetView> kept;
  for (std::size_t i = 0; i < std::size_t(count); ++i) kept.push_back(std::move(dataset.train[i * n / std::size_t(count)]));
  dataset.train = std::move(kept);
  dataset.scene_extent = dataset_detail::scene_extent(dataset.train);
}

float frame_background_share(const Image& image, const float background[3]) {
  if (image.width < 1 || image.height < 1) return 0.0f;
  constexpr float kHalfLevel = 0.5f / 255.0f;
  std::size_t frame = 0, plain = 0;
  const auto count = [&](int x, int y) {
    ++frame;
    bool same = true;
    for (int c = 0; c < 3; ++c) same = same && std::abs(image.at(x, y, c) - background[c]) <= kHalfLevel;
    plain += same;
  };
  for (int x = 0; x < image.width; ++x) {  // top and bottom rows (once when they are one)
    count(x, 0);
    if (image.height > 1) count(x, image.height - 1);
  }
  for (int y = 1; y + 1 < image.height; ++y) {  // left and right columns between them
    count(0, y);
    if (image.width > 1) count(image.width - 1, y);
  }
  return float(plain) / float(frame);
}

bool background_left_out(const std::vector<DatasetView>& views) {
  double share = 0;
  for (const DatasetView& view : views) share += view.frame_background_share;
  return !views.empty() && share >= 0.5 * double(views.size());
}

glm::vec3 mean_camera_centre(const std::vector<DatasetView>& views) {
  glm::vec3 mean(0.0f);
  for (const DatasetView& view : views) mean += view.camera.center_in_world() / float(views.size());
  return mean;
}

glm::vec3 scene_centre(const std::vector<DatasetView>& train, const PointCloud* points) {
  if (!points || points->size() == 0) return mean_camera_centre(train);
  std::vector<float> axis(points->size());
  glm::vec3 median;
  for (int a = 0; a < 3; ++a) {
    for (std::size_t i = 0; i < axis.size(); ++i) axis[i] = points->positions[3 * i + std::size_t(a)];
    const auto middle = axis.begin() + std::ptrdiff_t(axis.size() / 2);
    std::nth_element(axis.begin(), middle, axis.end());
    median[a] = *middle;
  }
  return median;
}

std::vector<Camera> cameras_of(const std::vector<DatasetView>& views) {
  std::vector<Camera> cameras;
  for (const DatasetView& view : views) cameras.push_back(view.camera);
  return cameras;
}

std::uint64_t views_fingerprint(const std::vector<DatasetView>& views) {
  std::uint64_t hash = splitmix64(views.size());
  const auto add = [&](std::uint64_t value) { hash = splitmix64(hash ^ value); };
  for (const DatasetView& view : views) {
    for (const char c : view.name) add(std::uint8_t(c));
    add((std::uint64_t(view.image.width) << 32) | std::uint64_t(view.image.height));
    add(std::uint64_t(view.image.channels));
    const std::vector<float>& data = view.image.data;
    for (std::size_t i = 0; i < data.size(); i += 2) {  // two floats a word
      std::uint32_t bits[2] = {0, 0};
      std::memcpy(bits, data.data() + i, std::min<std::size_t>(2, data.size() - i) * sizeof(float));
      add((std::uint64_t(bits[0]) << 32) | bits[1]);
    }
  }
  return hash;
}

}  // namespace splat
