#pragma once
// Internal to load_dataset: the folder kinds (dataset_blender.cpp, dataset_nerfstudio.cpp,
// dataset_colmap.cpp) and the steps they share (dataset.cpp).
#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "splat/core/camera.hpp"
#include "splat/core/image.hpp"
#include "splat/data/dataset.hpp"
#include "splat/data/transforms_json.hpp"
#include "splat/data/undistort.hpp"

namespace splat::dataset_detail {

Dataset load_blender(const std::filesystem::path& folder, const DatasetOptions& options);
Dataset load_nerfstudio(const std::filesystem::path& folder, const DatasetOptions& options);
Dataset load_colmap(const std::filesystem::path& folder, const std::filesystem::path& sparse_dir,
                    const DatasetOptions& options);

// The reduction an image of `width` x `height` is read at: the downscale when the whole image
// is beyond the pixel limit (kMaxImagePixels), so that a photograph of any size loads with
// --downscale (read_image_reduced: a JPEG decoded at 1/2..1/8 by libjpeg); else 1, read whole
// and downscaled after (undistortion, if any, at full size), as always.
int read_reduction(int width, int height, int downscale);

// `camera` at 1/reduction of its size (floor), intrinsics scaled; itself for reduction 1.
Camera reduced_camera(const Camera& camera, int reduction);

// Reads `file` at 1/`reduction` of its size as three channels: RGB as stored, RGBA composited
// onto `background` with straight alpha (rgb·a + bg·(1 − a)). InputError naming the file when
// it is missing, unreadable, has another channel count, or is not `width` x `height` (its full
// size); `size_source` says where that size comes from ("the camera in transforms_train.json").
Image read_rgb(const std::filesystem::path& file, int width, int height, int reduction,
               const std::string& size_source, const float background[3]);

// The view at 1/downscale of its size (floor), area-filtered (its mask too), intrinsics
// scaled. InputError naming `file` when the image is too small for the factor.
void downscale_view(DatasetView& view, int downscale, const std::filesystem::path& file);

// Where one view's photo comes from and what took it.
struct ViewSource {
  std::filesystem::path image;
  std::filesystem::path mask;  // nerfstudio's per-image mask; empty: none
  Camera camera;               // pinhole part and pose at the photo's full size
  LensDistortion distortion;
  // The part of the undistorted image the photo covers, at the size it is read at, when the
  // caller found it once for many views (a COLMAP camera); otherwise found here.
  std::optional<PixelRect> covered;
  std::string size_source;  // where the camera's size comes from, for messages
};

// The steps every folder kind shares for one view: read the photo (reduced while reading when
// beyond the pixel limit), undistort it to the pinhole image and cut it to what the photo
// covers, read its mask and carry it through the same steps, downscale. `view.name` is left
// to the caller. InputError naming the file for anything wrong with either image, and for a
// distortion that leaves less than half the image covered in either direction.
void load_view(const ViewSource& source, int downscale, const float background[3], DatasetView& view);

// `views`, in name order, split as DatasetOptions::holdout_every says (every 8th a test view
// by default, the LLFF / Mip-NeRF 360 habit the official 3DGS evaluation follows). InputError
// naming `source` when no training view is left.
Dataset split_by_holdout(std::vector<DatasetView> views, const DatasetOptions& options,
                         const std::filesystem::path& source);

// The source of a frame of a transforms file.
ViewSource view_source(const CameraFrame& frame, const std::filesystem::path& transforms);

// Every view's image is held in memory as float RGB (12 bytes a pixel) at 1/downscale of
// `sizes`. InputError naming `source` when that is more than half of this machine's memory
// (the trainer needs the rest), saying what --downscale would fit; checked before any image
// is read. (A dataset is the one input whose size has no fixed limit: captures of hundreds of
// photographs need gigabytes, and may have them.)
struct ImageSize {
  int width = 0, height = 0;
};
// The downscale the images load at: options.downscale, or with max_width > 0 and downscale 1,
// the smallest factor that brings the widest of `sizes` to at most max_width.
int chosen_downscale(const std::vector<ImageSize>& sizes, const DatasetOptions& options);

void check_dataset_fits_in_memory(const std::filesystem::path& source, const std::vector<ImageSize>& sizes,
                                  int downscale);

// Runs job(i) for every i in [0, count) in parallel. If any fail, rethrows the exception of
// the smallest failing i, so the error reported does not depend on thread timing.
void for_each_in_parallel(std::size_t count, const std::function<void(std::size_t)>& job);

// 1.1 × the largest distance of a camera centre from their mean (getNerfppNorm).
float scene_extent(const std::vector<DatasetView>& train);

}  // namespace splat::dataset_detail
