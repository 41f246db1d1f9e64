// load_dataset on bad folders: every failure is an InputError naming the file at fault.
#include "splat/data/dataset.hpp"

#include <gtest/gtest.h>

#include <string>

#include "tests/data/dataset_test_folders.hpp"
#include "splat/core/error.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;
using test::ModelForm;
using test::TestModel;

TestModel pinhole_model(int count) {
  TestModel m;
  m.cameras = {{1, ColmapCameraModel::kPinhole, 6, 4, {5, 5, 3, 2}}};
  for (int i = 0; i < count; ++i) {
    ColmapImage image;
    image.id = std::uint32_t(i + 1);
    image.translation = {0.0, 0.0, 2.0 + i};
    image.camera_id = 1;
    image.name = "im" + std::to_string(i) + ".png";
    m.images.push_back(image);
  }
  m.points = {{{0, 0, 0}, {1, 2, 3}}};
  return m;
}

// The InputError load_dataset throws for `folder`; fails the test if it throws nothing or
// something else.
InputError load_error(const fs::path& folder, const DatasetOptions& options = {}) {
  try {
    load_dataset(folder, options);
  } catch (const InputError& e) {
    return e;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected InputError, got: " << e.what();
    return InputError(folder, "wrong exception");
  }
  ADD_FAILURE() << "expected InputError for " << folder;
  return InputError(folder, "nothing thrown");
}

void expect_mentions(const InputError& e, const std::string& text) {
  EXPECT_NE(std::string(e.what()).find(text), std::string::npos)
      << "\"" << e.what() << "\" does not mention \"" << text << "\"";
}

TEST(DatasetErrors, FolderOfNeitherKind) {
  const fs::path dir = test::scratch_dir("dataset_error_neither");
  test::write_text(dir / "notes.txt", "hello");
  const InputError e = load_error(dir);
  EXPECT_EQ(e.file(), dir);
  expect_mentions(e, "transforms_train.json");
  expect_mentions(e, "sparse/0");
  EXPECT_EQ(load_error(dir / "absent").file(), dir / "absent");
  EXPECT_EQ(load_error(dir / "notes.txt").file(), dir / "notes.txt");
}

TEST(DatasetErrors, BlenderWithoutTestOrValidationSplit) {
  const fs::path dir = test::scratch_dir("dataset_error_no_test");
  test::write_blender_folder(dir, 4, 4, 2, 1);
  fs::remove(dir / "transforms_test.json");
  const InputError e = load_error(dir);
  EXPECT_EQ(e.file(), dir / "transforms_test.json");
  expect_mentions(e, "transforms_val.json");
}

TEST(DatasetErrors, BlenderMissingImageNamesTheFirstMissingImage) {
  const fs::path dir = test::scratch_dir("dataset_error_blender_missing");
  test::write_blender_folder(dir, 4, 4, 12, 3);
  fs::remove(dir / "train" / "r_9.png");
  fs::remove(dir / "test" / "t_2.png");
  fs::remove(dir / "train" / "r_4.png");
  // Whichever thread fails first, the error is the one in list order.
  for (int attempt = 0; attempt < 5; ++attempt) {
    const InputError e = load_error(dir);
    EXPECT_EQ(e.file(), dir / "train" / "r_4.png");
    expect_mentions(e, "does not exist");
  }
}

TEST(DatasetErrors, BlenderImageOfTheWrongSizeOrChannels) {
  const fs::path dir = test::scratch_dir("dataset_error_blender_size");
  test::write_blender_folder(dir, 4, 4, 3, 1);
  write_png(test::code_pattern(5, 4, 4, 0), dir / "train" / "r_2.png");
  InputError e = load_error(dir);
  EXPECT_EQ(e.file(), dir / "train" / "r_2.png");
  expect_mentions(e, "5 x 4");
  expect_mentions(e, "4 x 4");
  expect_mentions(e, "transforms_train.json");

  write_png(test::code_pattern(4, 4, 2, 0), dir / "train" / "r_2.png");  // grey + alpha
  e = load_error(dir);
  EXPECT_EQ(e.file(), dir / "train" / "r_2.png");
  expect_mentions(e, "2 channels");
}

TEST(DatasetErrors, BlenderTransformsWithoutFrames) {
  const fs::path dir = test::scratch_dir("dataset_error_no_frames");
  test::write_blender_folder(dir, 4, 4, 1, 1);
  test::write_text(dir / "transforms_train.json", R"({"camera_angle_x":0.8,"frames":[]})");
  EXPECT_EQ(load_error(dir).file(), dir / "transforms_train.json");
}

TEST(DatasetErrors, ColmapMissingAndWrongSizeImages) {
  const fs::path dir = test::scratch_dir("dataset_error_colmap_images");
  test::write_colmap_folder(dir, pinhole_model(4), ModelForm::kText);
  fs::remove(dir / "images" / "im2.png");
  InputError e = load_error(dir);
  EXPECT_EQ(e.file(), dir / "images" / "im2.png");

  test::write_colmap_folder(dir, pinhole_model(4), ModelForm::kText);
  write_png(test::code_pattern(6, 5, 3, 0), dir / "images" / "im1.png");
  e = load_error(dir);
  EXPECT_EQ(e.file(), dir / "images" / "im1.png");
  expect_mentions(e, "6 x 5");
  expect_mentions(e, "6 x 4");
  expect_mentions(e, "cameras.txt");
}

TEST(DatasetErrors, ColmapUnsupportedCameraModels) {
  const fs::path dir = test::scratch_dir("dataset_error_colmap_model");
  TestModel model = pinhole_model(3);
  // FULL_OPENCV (id 6) in text, OPENCV_FISHEYE (id 5) in binary.
  test::write_colmap_folder(dir / "text", model, ModelForm::kText);
  test::write_text(dir / "text" / "sparse" / "0" / "cameras.txt",
                   "1 FULL_OPENCV 6 4 5 5 3 2 0 0 0 0 0 0 0 0\n");
  InputError e = load_error(dir / "text");
  EXPECT_EQ(e.file(), dir / "text" / "sparse" / "0" / "cameras.txt");
  expect_mentions(e, "FULL_OPENCV");

  model.cameras[0].model = ColmapCameraModel(5);
  model.cameras[0].params = {5, 5, 3, 2, 0.1, 0, 0, 0};
  test::write_colmap_folder(dir / "binary", model, ModelForm::kBinary);
  e = load_error(dir / "binary");
  EXPECT_EQ(e.file(), dir / "binary" / "sparse" / "0" / "cameras.bin");
  expect_mentions(e, "OPENCV_FISHEYE");
}

TEST(DatasetErrors, ColmapLensThatCoversTooLittle) {
  // A distortion so strong that most of the pinhole image would be background.
  const fs::path dir = test::scratch_dir("dataset_error_colmap_lens");
  TestModel model = pinhole_model(3);
  model.cameras[0].model = ColmapCameraModel::kOpenCv;
  model.cameras[0].params = {5, 5, 3, 2, 40.0, 0, 0, 0};
  test::write_colmap_folder(dir, model, ModelForm::kText);
  const InputError e = load_error(dir);
  EXPECT_EQ(e.file(), dir / "sparse" / "0" / "cameras.txt");
  expect_mentions(e, "distortion leaves only");
}

TEST(DatasetErrors, ColmapEmptyPointCloud) {
  const fs::path dir = test::scratch_dir("dataset_error_colmap_points");
  TestModel model = pinhole_model(3);
  model.points.clear();
  test::write_colmap_folder(dir, model, ModelForm::kBinary);
  const InputError e = load_error(dir);
  EXPECT_EQ(e.file(), dir / "sparse" / "0" / "points3D.bin");
  expect_mentions(e, "empty");
}

TEST(DatasetErrors, ColmapTruncatedBinary) {
  const fs::path dir = test::scratch_dir("dataset_error_colmap_truncated");
  test::write_colmap_folder(dir, pinhole_model(3), ModelForm::kBinary);
  const fs::path images = dir / "sparse" / "0" / "images.bin";
  fs::resize_file(images, fs::file_size(images) - 3);
  const InputError e = load_error(dir);
  EXPECT_EQ(e.file(), images);
  expect_mentions(e, "truncated");
}

TEST(DatasetErrors, ColmapMissingSparseFiles) {
  const fs::path dir = test::scratch_dir("dataset_error_colmap_sparse");
  fs::create_directories(dir / "sparse" / "0");
  fs::create_directories(dir / "images");
  InputError e = load_error(dir);
  expect_mentions(e, "cameras.bin or cameras.txt");
  EXPECT_EQ(e.file().parent_path(), dir / "sparse" / "0");

  test::write_colmap_folder(dir, pinhole_model(3), ModelForm::kText);
  fs::remove(dir / "sparse" / "0" / "points3D.txt");
  e = load_error(dir);
  expect_mentions(e, "points3D.bin or points3D.txt");
}

TEST(DatasetErrors, ColmapImageWithUnknownCamera) {
  const fs::path dir = test::scratch_dir("dataset_error_colmap_camera_id");
  TestModel model = pinhole_model(3);
  test::write_colmap_folder(dir, model, ModelForm::kText);
  model.images[1].camera_id = 9;
  test::write_colmap_text(model, dir / "sparse" / "0");
  const InputError e = load_error(dir);
  EXPECT_EQ(e.file(), dir / "sparse" / "0" / "images.txt");
  expect_mentions(e, "camera id 9");
}

TEST(DatasetErrors, ColmapWithNothingLeftToTrainOn) {
  const fs::path dir = test::scratch_dir("dataset_error_colmap_one_image");
  test::write_colmap_folder(dir, pinhole_model(1), ModelForm::kText);
  EXPECT_EQ(load_error(dir).file(), dir / "sparse" / "0" / "images.txt");
}

// The images' sizes are known from the transforms before any is read: 2,000 views of
// 4,096 x 4,096 would take 403 GB as float RGB, more than any machine this runs on has, so
// the folder is refused at once with a --downscale that fits (none of the images exists).
TEST(DatasetErrors, ADatasetTooLargeForMemoryNamesTheFolderAndADownscaleThatFits) {
  const fs::path dir = test::scratch_dir("dataset_error_too_large");
  test::write_blender_folder(dir, 4, 4, 1, 1);
  std::string transforms = test::transforms_json("train", "huge", 2000);
  transforms.replace(0, 1, R"({"w": 4096, "h": 4096, )");
  test::write_text(dir / "transforms_train.json", transforms);
  const InputError e = load_error(dir);
  EXPECT_EQ(e.file(), dir);
  expect_mentions(e, "its 2001 images take 402.7 GB in memory");
  expect_mentions(e, "--downscale ");
}

TEST(DatasetErrors, DownscaleOutOfRange) {
  const fs::path dir = test::scratch_dir("dataset_error_downscale");
  test::write_blender_folder(dir, 4, 4, 1, 1);
  DatasetOptions options;
  options.downscale = 5;  // 4 / 5 leaves no pixel
  const InputError e = load_error(dir, options);
  EXPECT_EQ(e.file(), dir / "train" / "r_0.png");
  options.downscale = 0;
  EXPECT_THROW(load_dataset(dir, options), ArgumentError);
}

}  // namespace
}  // namespace splat
