// load_dataset on small folders written by the tests, where every value is known.
#include "splat/data/dataset.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "tests/data/dataset_test_folders.hpp"
#include "splat/core/error.hpp"
#include "splat/data/dataset_loading.hpp"
#include "splat/data/undistort.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;
using test::ModelForm;
using test::TestModel;

constexpr float kWhite[3] = {1, 1, 1};

std::string image_name(int i) {
  char text[16];
  std::snprintf(text, sizeof text, "img_%02d.png", i);
  return text;
}

// One camera of every supported model and `count` images listed in a scrambled order,
// cycling through the cameras.
TestModel folder_model(int count) {
  TestModel m;
  m.cameras = {
      {1, ColmapCameraModel::kSimplePinhole, 8, 6, {7.5, 4, 3}},
      {2, ColmapCameraModel::kPinhole, 8, 6, {7.5, 8.25, 4.1, 2.9}},
      {3, ColmapCameraModel::kSimpleRadial, 8, 6, {7.5, 4, 3, 0.05}},
      {4, ColmapCameraModel::kRadial, 10, 7, {9.5, 5, 3.5, 0.05, -0.01}},
      {5, ColmapCameraModel::kOpenCv, 8, 6, {7.5, 8, 4, 3, 0.05, -0.01, 0.002, -0.003}},
  };
  for (int k = 0; k < count; ++k) {
    const int i = (k * 7) % count;  // scrambled: file order is not name order
    ColmapImage image;
    image.id = std::uint32_t(100 + k);
    image.quaternion = test::axis_angle_quaternion(0.3, 1, -0.2 * i, 0.2 + 0.1 * i);
    image.translation = {0.1 * i, 0.2, 3.0 + 0.05 * i};
    image.camera_id = std::uint32_t(1 + i % 5);
    image.name = image_name(i);
    m.images.push_back(image);
  }
  for (int i = 0; i < 4; ++i)
    m.points.push_back({{0.5 * i, 1.0 - i, 0.25}, {std::uint8_t(60 * i), 17, 255}});
  return m;
}

const ColmapImage& image_named(const TestModel& m, const std::string& name) {
  for (const ColmapImage& image : m.images)
    if (image.name == name) return image;
  throw std::runtime_error("no image " + name);
}

// Rotation by `angle` about `axis` (Rodrigues), independent of the quaternion formula.
glm::mat3 rodrigues(double ax, double ay, double az, double angle) {
  const double n = std::sqrt(ax * ax + ay * ay + az * az);
  const double k[3] = {ax / n, ay / n, az / n};
  const double c = std::cos(angle), s = std::sin(angle);
  glm::mat3 r;
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col) {
      const double cross = row == col ? 0 : (((col - row + 3) % 3 == 1) ? -1 : 1) * k[3 - row - col];
      r[col][row] = float((row == col ? c : 0) + s * cross + (1 - c) * k[row] * k[col]);
    }
  return r;
}

void expect_same_views(const std::vector<DatasetView>& a, const std::vector<DatasetView>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].name, b[i].name);
    EXPECT_EQ(a[i].image.data, b[i].image.data) << a[i].name;
    EXPECT_EQ(a[i].camera.camera_from_world_rotation, b[i].camera.camera_from_world_rotation);
    EXPECT_EQ(a[i].camera.camera_from_world_translation, b[i].camera.camera_from_world_translation);
    EXPECT_EQ(a[i].camera.fx, b[i].camera.fx);
    EXPECT_EQ(a[i].camera.cy, b[i].camera.cy);
    EXPECT_EQ(a[i].camera.width, b[i].camera.width);
  }
}

TEST(DatasetFolders, BlenderCompositesStraightAlphaOntoTheBackground) {
  const fs::path dir = test::scratch_dir("dataset_blender_alpha");
  test::write_blender_folder(dir, 6, 5, 2, 1);
  DatasetOptions options;
  options.background[0] = 0.2f, options.background[1] = 0.4f, options.background[2] = 0.6f;
  const Dataset d = load_dataset(dir, options);
  ASSERT_EQ(d.train.size(), 2u);
  ASSERT_EQ(d.test.size(), 1u);
  EXPECT_EQ(d.train[1].name, "r_1");
  EXPECT_EQ(d.test[0].name, "t_0");
  const Image rgba = read_image(dir / "train" / "r_1.png");
  const Image& rgb = d.train[1].image;
  ASSERT_EQ(rgb.channels, 3);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 6; ++x)
      for (int c = 0; c < 3; ++c) {
        const float a = rgba.at(x, y, 3);
        EXPECT_NEAR(rgb.at(x, y, c), rgba.at(x, y, c) * a + options.background[c] * (1 - a), 1e-6f);
      }
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(rgb.at(0, 0, c), options.background[c]);  // alpha 0
    EXPECT_EQ(rgb.at(1, 0, c), rgba.at(1, 0, c));        // alpha 1
  }
  // The opacity is kept beside the composited colour (the NeRF trainer's random backgrounds).
  const Image& alpha = d.train[1].alpha;
  ASSERT_EQ(alpha.channels, 1);
  ASSERT_EQ(alpha.width, 6);
  ASSERT_EQ(alpha.height, 5);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 6; ++x) EXPECT_EQ(alpha.at(x, y, 0), rgba.at(x, y, 3));
  // Camera centres at (0.5k, -0.25k, 4) for k = 0, 1: mean in between, 1.1 × half the gap.
  EXPECT_NEAR(d.scene_extent, 1.1f * 0.5f * std::sqrt(0.25f + 0.0625f), 1e-6f);
}

TEST(DatasetFolders, BlenderRgbImagesAndValidationSplit) {
  const fs::path dir = test::scratch_dir("dataset_blender_val");
  test::write_blender_folder(dir, 4, 4, 1, 2, /*channels=*/3, "transforms_val.json");
  const Dataset d = load_dataset(dir);
  ASSERT_EQ(d.test.size(), 2u);
  EXPECT_EQ(d.test[1].name, "t_1");
  EXPECT_EQ(d.test[1].image.data, read_image(dir / "test" / "t_1.png").data);
  EXPECT_TRUE(d.test[1].alpha.empty());  // no alpha channel: nothing kept
  // A single training camera has no spread; the extent falls back to 1.
  EXPECT_EQ(d.scene_extent, 1.0f);
}

TEST(DatasetFolders, ViewsSayHowMuchOfTheirFrameIsPlainBackground) {
  // A 6 x 5 image has a frame of 18 pixels. code_pattern's alpha is 0 at (0, 0) only, so
  // composited that one shows the background; paint five more of them in its colour, and
  // one inside the frame, which does not count.
  const fs::path dir = test::scratch_dir("dataset_blender_frame");
  test::write_blender_folder(dir, 6, 5, 2, 1);
  Image rgba = test::code_pattern(6, 5, 4, 1);
  const float grey[3] = {0.2f, 0.4f, 0.6f};
  for (auto [x, y] : {std::pair{1, 0}, {5, 0}, {0, 4}, {5, 2}, {3, 4}, {2, 2}})
    for (int c = 0; c < 4; ++c) rgba.at(x, y, c) = c < 3 ? grey[c] : 1.0f;
  write_png(rgba, dir / "train" / "r_1.png");
  DatasetOptions options;
  std::copy(grey, grey + 3, options.background);
  const Dataset d = load_dataset(dir, options);
  EXPECT_FLOAT_EQ(d.train[1].frame_background_share, 6.0f / 18.0f);
  EXPECT_FLOAT_EQ(d.train[0].frame_background_share, 1.0f / 18.0f);
  // Against another background only the transparent pixel matches.
  const Dataset white = load_dataset(dir);
  EXPECT_FLOAT_EQ(white.train[1].frame_background_share, 1.0f / 18.0f);
  EXPECT_FLOAT_EQ(white.test[0].frame_background_share, 1.0f / 18.0f);
  // Whole images: all background, none; one row.
  const float white_rgb[3] = {1, 1, 1};
  EXPECT_EQ(frame_background_share(Image(4, 3, 3, 1.0f), white_rgb), 1.0f);
  EXPECT_EQ(frame_background_share(Image(4, 3, 3, 0.9f), white_rgb), 0.0f);
  EXPECT_EQ(frame_background_share(Image(4, 1, 3, 1.0f), white_rgb), 1.0f);
}

TEST(DatasetFolders, ColmapTextAndBinaryLoadTheSame) {
  const fs::path dir = test::scratch_dir("dataset_colmap_forms");
  const TestModel model = folder_model(10);
  test::write_colmap_folder(dir / "text", model, ModelForm::kText);
  test::write_colmap_folder(dir / "binary", model, ModelForm::kBinary);
  const Dataset text = load_dataset(dir / "text");
  const Dataset binary = load_dataset(dir / "binary");
  expect_same_views(text.train, binary.train);
  expect_same_views(text.test, binary.test);
  ASSERT_TRUE(text.points && binary.points);
  EXPECT_EQ(text.points->positions, binary.points->positions);
  EXPECT_EQ(text.points->colors, binary.points->colors);
  EXPECT_EQ(text.scene_extent, binary.scene_extent);
  ASSERT_EQ(binary.points->size(), 4u);
  EXPECT_EQ(binary.points->positions[3 * 3 + 1], -2.0f);
  EXPECT_EQ(binary.points->colors[3 * 3 + 0], 180.0f / 255.0f);
}

TEST(DatasetFolders, ColmapSplitPosesAndIntrinsics) {
  const fs::path dir = test::scratch_dir("dataset_colmap_split");
  const TestModel model = folder_model(10);
  test::write_colmap_folder(dir, model, ModelForm::kBinary);
  const Dataset d = load_dataset(dir);
  // Name order img_00 .. img_09; every 8th (0 and 8) is a test view.
  ASSERT_EQ(d.test.size(), 2u);
  ASSERT_EQ(d.train.size(), 8u);
  EXPECT_EQ(d.test[0].name, "img_00");
  EXPECT_EQ(d.test[1].name, "img_08");
  const std::vector<std::string> train_names = {"img_01", "img_02", "img_03", "img_04",
                                                "img_05", "img_06", "img_07", "img_09"};
  for (std::size_t i = 0; i < train_names.size(); ++i) EXPECT_EQ(d.train[i].name, train_names[i]);

  for (const auto* split : {&d.train, &d.test})
    for (const DatasetView& v : *split) {
      const int i = std::stoi(v.name.substr(4));
      const glm::mat3 expected = rodrigues(0.3, 1, -0.2 * i, 0.2 + 0.1 * i);
      for (int col = 0; col < 3; ++col)
        for (int row = 0; row < 3; ++row)
          EXPECT_NEAR(v.camera.camera_from_world_rotation[col][row], expected[col][row], 1e-6)
              << v.name;
      const ColmapImage& image = image_named(model, v.name + ".png");
      for (int a = 0; a < 3; ++a)
        EXPECT_FLOAT_EQ(v.camera.camera_from_world_translation[a], float(image.translation[a]));
      // Intrinsics carry over unchanged (COLMAP's pixel centres are at i + 0.5 too).
      const ColmapCamera& cam = model.cameras[std::size_t(image.camera_id - 1)];
      const bool two_focals = cam.model == ColmapCameraModel::kPinhole ||
                              cam.model == ColmapCameraModel::kOpenCv;
      EXPECT_FLOAT_EQ(v.camera.fx, float(cam.params[0])) << v.name;
      EXPECT_FLOAT_EQ(v.camera.fy, float(cam.params[two_focals ? 1 : 0])) << v.name;
      EXPECT_FLOAT_EQ(v.camera.cx, float(cam.params[two_focals ? 2 : 1])) << v.name;
      EXPECT_FLOAT_EQ(v.camera.cy, float(cam.params[two_focals ? 3 : 2])) << v.name;
      EXPECT_EQ(v.camera.width, cam.width);
      EXPECT_EQ(v.image.width, cam.width);
      EXPECT_EQ(v.image.height, cam.height);
    }
  // img_00 uses camera 1, SIMPLE_PINHOLE: its image is the file as written.
  EXPECT_EQ(d.test[0].image.data, read_image(dir / "images" / "img_00.png").data);
}

TEST(DatasetFolders, ColmapDistortedCamerasAreUndistorted) {
  const fs::path dir = test::scratch_dir("dataset_colmap_distorted");
  TestModel model = folder_model(10);
  test::write_colmap_folder(dir, model, ModelForm::kText);
  const Dataset d = load_dataset(dir);
  // img_04 uses camera 5 (OPENCV), img_03 camera 4 (RADIAL), img_02 camera 3 (SIMPLE_RADIAL).
  const std::pair<std::string, LensDistortion> cases[] = {
      {"img_04", {0.05, -0.01, 0.002, -0.003}},
      {"img_03", {0.05, -0.01, 0, 0}},
      {"img_02", {0.05, 0, 0, 0}},
  };
  for (const auto& [name, distortion] : cases) {
    const DatasetView* view = nullptr;
    for (const DatasetView& v : d.train)
      if (v.name == name) view = &v;
    ASSERT_NE(view, nullptr) << name;
    const Image raw = read_image(dir / "images" / (name + ".png"));
    // The view is the pinhole image less the border the lens does not cover; its camera
    // is the pinhole camera cropped alike.
    const ColmapImage& image = image_named(model, name + ".png");
    const ColmapCamera& colmap = model.cameras[std::size_t(image.camera_id - 1)];
    Camera pinhole = view->camera;
    pinhole.width = colmap.width;
    pinhole.height = colmap.height;
    const bool two_focals = colmap.model == ColmapCameraModel::kOpenCv;
    pinhole.cx = float(colmap.params[two_focals ? 2 : 1]);
    pinhole.cy = float(colmap.params[two_focals ? 3 : 2]);
    const PixelRect covered = covered_region(pinhole, distortion);
    const Image expected = crop_image(undistort_image(raw, pinhole, distortion, kWhite), covered);
    EXPECT_EQ(view->image.data, expected.data) << name;
    EXPECT_EQ(view->image.width, covered.width) << name;
    EXPECT_EQ(view->camera.width, covered.width) << name;
    EXPECT_EQ(view->camera.height, covered.height) << name;
    EXPECT_FLOAT_EQ(view->camera.cx, pinhole.cx - float(covered.x0)) << name;
    EXPECT_FLOAT_EQ(view->camera.cy, pinhole.cy - float(covered.y0)) << name;
  }

  // These lenses are gentle enough to cover the tiny images; a strong one leaves a border,
  // which is cut off, and the principal point moves with the cut.
  TestModel strong = model;
  strong.cameras[4].params[4] = 1.0;  // OPENCV k1
  const fs::path strong_dir = test::scratch_dir("dataset_colmap_strong_lens");
  test::write_colmap_folder(strong_dir, strong, ModelForm::kText);
  const Dataset cut = load_dataset(strong_dir);
  int strong_views = 0;
  for (const DatasetView& v : cut.train)
    if (v.name == "img_04") {
      ++strong_views;
      EXPECT_LT(v.camera.width * v.camera.height, 8 * 6);
      EXPECT_EQ(v.image.width, v.camera.width);
      EXPECT_EQ(v.image.height, v.camera.height);
      EXPECT_LT(v.camera.cx, 4.0f);
    }
  EXPECT_EQ(strong_views, 1);

  // With every coefficient zero the lens is a pinhole: the image comes back as it is.
  // The coefficients follow the focal lengths and principal point: 3 of those for
  // SIMPLE_RADIAL and RADIAL, 4 for OPENCV.
  model.cameras[2].params[3] = 0;
  model.cameras[3].params[3] = model.cameras[3].params[4] = 0;
  for (std::size_t k = 4; k < 8; ++k) model.cameras[4].params[k] = 0;
  const fs::path zero = test::scratch_dir("dataset_colmap_zero_distortion");
  test::write_colmap_folder(zero, model, ModelForm::kBinary);
  const Dataset undistorted = load_dataset(zero);
  for (const DatasetView& v : undistorted.train)
    EXPECT_EQ(v.image.data, read_image(zero / "images" / (v.name + ".png")).data) << v.name;
}

TEST(DatasetFolders, TrainingViewsCanBeThinnedWithTheTestViewsKept) {
  const fs::path dir = test::scratch_dir("dataset_colmap_train_views");
  test::write_colmap_folder(dir, folder_model(10), ModelForm::kBinary);
  DatasetOptions options;
  options.train_views = 3;
  const Dataset d = load_dataset(dir, options);
  // Training views img_01 .. img_07, img_09 (8 of them); views 0, 8/3, 16/3 -> 0, 2, 5 are kept.
  ASSERT_EQ(d.train.size(), 3u);
  EXPECT_EQ(d.train[0].name, "img_01");
  EXPECT_EQ(d.train[1].name, "img_03");
  EXPECT_EQ(d.train[2].name, "img_06");
  ASSERT_EQ(d.test.size(), 2u);
  EXPECT_EQ(d.test[0].name, "img_00");
  EXPECT_EQ(d.test[1].name, "img_08");
  // The extent is that of the kept cameras (what a sparser capture would give).
  EXPECT_FLOAT_EQ(d.scene_extent, dataset_detail::scene_extent(d.train));
  options.train_views = 8;  // all of them
  EXPECT_EQ(load_dataset(dir, options).train.size(), 8u);
  options.train_views = 9;  // more than there are: a mistake, said so
  try {
    load_dataset(dir, options);
    ADD_FAILURE() << "--train-views beyond the views was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--train-views 9 asks for more views than the 8 training views"),
              std::string::npos) << e.what();
  }
}

// --holdout-every K: every K-th image in name order is a test view; 0 holds none out. Blender
// folders name their test views and refuse it; a negative K is refused.
TEST(DatasetFolders, ColmapHoldsOutEveryKthViewOrNone) {
  const fs::path dir = test::scratch_dir("dataset_colmap_holdout");
  test::write_colmap_folder(dir, folder_model(10), ModelForm::kBinary);
  DatasetOptions options;
  options.holdout_every = 4;
  Dataset d = load_dataset(dir, options);
  ASSERT_EQ(d.test.size(), 3u);  // img_00, img_04, img_08
  EXPECT_EQ(d.test[0].name, "img_00");
  EXPECT_EQ(d.test[1].name, "img_04");
  EXPECT_EQ(d.test[2].name, "img_08");
  EXPECT_EQ(d.train.size(), 7u);
  options.holdout_every = 0;
  d = load_dataset(dir, options);
  EXPECT_TRUE(d.test.empty());
  ASSERT_EQ(d.train.size(), 10u);
  EXPECT_EQ(d.train[0].name, "img_00");
  options.holdout_every = 1;  // every view a test view: nothing to train on
  EXPECT_THROW(load_dataset(dir, options), InputError);
  options.holdout_every = -1;
  EXPECT_THROW(load_dataset(dir, options), ArgumentError);

  const fs::path blender = test::scratch_dir("dataset_blender_holdout");
  test::write_blender_folder(blender, 4, 4, 2, 1, /*channels=*/3, "transforms_test.json");
  options.holdout_every = 8;
  try {
    load_dataset(blender, options);
    ADD_FAILURE() << "a Blender folder took --holdout-every";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("transforms_test.json"), std::string::npos) << e.what();
  }
}

TEST(DatasetFolders, ColmapModelDirectlyInSparse) {
  const fs::path dir = test::scratch_dir("dataset_colmap_sparse_flat");
  test::write_colmap_folder(dir, folder_model(3), ModelForm::kText);
  for (const char* file : {"cameras.txt", "images.txt", "points3D.txt"})
    fs::rename(dir / "sparse" / "0" / file, dir / "sparse" / file);
  fs::remove(dir / "sparse" / "0");
  const Dataset d = load_dataset(dir);
  EXPECT_EQ(d.train.size(), 2u);
  EXPECT_EQ(d.test.size(), 1u);
}

TEST(DatasetFolders, ColmapDownscaleScalesEachAxis) {
  const fs::path dir = test::scratch_dir("dataset_colmap_downscale");
  test::write_colmap_folder(dir, folder_model(3), ModelForm::kBinary);
  DatasetOptions options;
  options.downscale = 3;
  const Dataset d = load_dataset(dir, options);
  // img_00: SIMPLE_PINHOLE 8 x 6 -> 2 x 2, so x scales by 1/4 and y by 1/3.
  const DatasetView& v = d.test[0];
  ASSERT_EQ(v.name, "img_00");
  EXPECT_EQ(v.image.width, 2);
  EXPECT_EQ(v.image.height, 2);
  EXPECT_EQ(v.camera.width, 2);
  EXPECT_EQ(v.camera.height, 2);
  EXPECT_FLOAT_EQ(v.camera.fx, 7.5f / 4);
  EXPECT_FLOAT_EQ(v.camera.cx, 4.0f / 4);
  EXPECT_FLOAT_EQ(v.camera.fy, 7.5f / 3);
  EXPECT_FLOAT_EQ(v.camera.cy, 3.0f / 3);
  // Pixel (0, 0) averages input columns [0, 4) and rows [0, 3).
  const Image raw = read_image(dir / "images" / "img_00.png");
  for (int c = 0; c < 3; ++c) {
    float sum = 0;
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 4; ++x) sum += raw.at(x, y, c);
    EXPECT_NEAR(v.image.at(0, 0, c), sum / 12, 1e-6f);
  }
}

TEST(DatasetFolders, LoadingIsDeterministic) {
  const fs::path dir = test::scratch_dir("dataset_colmap_deterministic");
  test::write_colmap_folder(dir, folder_model(17), ModelForm::kBinary);
  const Dataset a = load_dataset(dir), b = load_dataset(dir);
  expect_same_views(a.train, b.train);
  expect_same_views(a.test, b.test);
  EXPECT_EQ(a.test.size(), 3u);  // 0, 8, 16
}

}  // namespace
}  // namespace splat
