#pragma once
// Training datasets: Blender / NeRF-synthetic, nerfstudio and COLMAP folders, detected
// automatically (docs/DESIGN.md, "--data").
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "splat/core/camera.hpp"
#include "splat/core/image.hpp"
#include "splat/core/setting_value.hpp"

namespace splat {

struct DatasetView {
  std::string name;        // image base name, e.g. "r_1" or "000"
  Camera camera;           // pinhole, internal convention, at the loaded (downscaled) size
  Image image;             // [H, W, 3] in [0, 1], alpha composited onto the background
  // [H, W, 1] weights in [0, 1] from a nerfstudio mask: pixels at 0 are neither trained on
  // nor scored. Empty (the usual case): every pixel counts.
  Image mask = {};
  // [H, W, 1] the file's opacity, where it had an alpha channel that is not 1 everywhere;
  // empty otherwise. `image` is already composited with it; a trainer that wants another
  // background behind a pixel recovers it as image + (1 − alpha)(other − background).
  Image alpha = {};
  // The share of the image's frame (its outermost rows and columns) that shows only the
  // plain background it was composited onto: transparent in the file, or that colour
  // exactly. Near 1 for an object rendered or photographed on its own, near 0 when the
  // scene reaches the frame (a room, a landscape, a sky of another colour).
  float frame_background_share = 0;
};

// Points to initialise Gaussians from (COLMAP points3D).
struct PointCloud {
  std::vector<float> positions;  // [P, 3]
  std::vector<float> colors;     // [P, 3] in [0, 1]
  std::size_t size() const { return positions.size() / 3; }
};

// Images wider than this train at a downscale by default (splat-train, splat-eval), as the
// official trainer rescales them: its time per iteration grows with the pixels.
constexpr int kDefaultMaxImageWidth = 1600;
// What the options that choose views and sizes may be (--downscale, --train-views, --holdout-every).
constexpr SettingRange kDownscaleRange{1, 256};
constexpr int kMaxViews = 1'000'000;

struct DatasetOptions {
  float background[3] = {1, 1, 1};  // RGBA images are composited onto this
  int downscale = 1;                // images resampled to 1/downscale (area filter), intrinsics scaled
  // > 0 with downscale 1: the loader picks the smallest downscale K at which every image is at
  // most this wide (Dataset::downscale says which), as the official trainer rescales images
  // wider than 1,600 pixels; 0: none.
  int max_width = 0;
  // Train on this many of the training views (keep_training_views), 0 = all; the test views
  // stay as they are: a sparser capture of the same scene, scored on the same views.
  int train_views = 0;
  // COLMAP and nerfstudio data: every K-th image in name order is a test view (i % K == 0),
  // 0 = none, all views train. Blender data names its test views in transforms_test.json, and
  // setting this for it is an error.
  std::optional<int> holdout_every;
};

struct Dataset {
  std::vector<DatasetView> train, test;
  std::optional<PointCloud> points;  // COLMAP: points3D; Blender: none
  // NeRF++-style normalisation radius as the official trainer computes it: 1.1 × the largest
  // distance of a training camera centre from their mean. Scales position learning rates and
  // the densification thresholds.
  float scene_extent = 1.0f;
  int downscale = 1;  // the factor the images were loaded at (DatasetOptions::downscale or picked)
};

// Loads `folder`: a Blender folder (transforms_train.json, and transforms_test.json or
// transforms_val.json), a nerfstudio folder (transforms.json: every view, OPENCV lenses and
// masks; split as COLMAP data) or a COLMAP folder (sparse/0/{cameras,images,points3D}.{bin,txt}
// and images/). COLMAP: PINHOLE and SIMPLE_PINHOLE as they are; SIMPLE_RADIAL, RADIAL and OPENCV
// undistorted on load to a pinhole camera with the same focal length and principal point;
// test views are every 8th image in name order (i % 8 == 0), or as DatasetOptions::holdout_every
// says. Throws InputError naming the file on missing or unreadable images, images of the wrong
// size, a transforms file without frames, an unknown camera model, an empty point cloud, or a
// folder of neither kind.
Dataset load_dataset(const std::filesystem::path& folder, const DatasetOptions& options = {});

// Keeps `count` of the training views, spread evenly through their order (view i·n/count for
// i < count; all of them when count ≥ n), and recomputes the scene extent from those kept,
// as it would be for a dataset that only had them. The test views are untouched.
void keep_training_views(Dataset& dataset, int count);

// DatasetView::frame_background_share of `image` (RGB) against `background`: a pixel shows
// the background when every channel is within half an 8-bit level of it.
float frame_background_share(const Image& image, const float background[3]);

// Whether `views` leave the background out: on average at least half of their frames show
// the plain colour they were composited onto (an object on its own, with nothing to draw
// around it), rather than scene that reaches the frame. Where a scene ends follows from it.
bool background_left_out(const std::vector<DatasetView>& views);

// The mean of the training cameras' centres (the middle of a capture around a scene).
glm::vec3 mean_camera_centre(const std::vector<DatasetView>& views);

// Where the scene is: the per-axis median of `points` (robust to stray points), or without
// points the mean of the training cameras' centres (the middle of a capture around it).
glm::vec3 scene_centre(const std::vector<DatasetView>& train, const PointCloud* points);

// The cameras of `views`, in order.
std::vector<Camera> cameras_of(const std::vector<DatasetView>& views);

// A 64-bit fingerprint of `views`: their names, sizes and pixels. A checkpoint records its
// training views' fingerprint, so that it resumes only on the images it was trained on.
std::uint64_t views_fingerprint(const std::vector<DatasetView>& views);

}  // namespace splat
