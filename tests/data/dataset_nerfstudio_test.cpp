// nerfstudio folders (one transforms.json): the split in name order, OpenCV lenses undistorted
// as COLMAP's are, per-image masks carried through the same steps, and clear errors.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "splat/core/error.hpp"
#include "splat/data/dataset.hpp"
#include "splat/data/resample.hpp"
#include "splat/data/undistort.hpp"
#include "tests/cli_support.hpp"
#include "tests/data/dataset_test_folders.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

constexpr float kWhite[3] = {1, 1, 1};
constexpr int kWidth = 24, kHeight = 18;
constexpr const char* kLens = R"("camera_model":"OPENCV","k1":0.05,"k2":-0.01,"p1":0.002,"p2":-0.003)";

std::string frame_name(int i) { return "frame_" + std::string(i < 10 ? "0" : "") + std::to_string(i); }

// A mask keeping the left two thirds of the image, with a soft column between.
Image left_mask() {
  Image mask(kWidth, kHeight, 1);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) mask.at(x, y, 0) = x < 16 ? 1.0f : x == 16 ? 0.6f : 0.0f;
  return mask;
}

// `count` frames listed in scrambled order, file-level intrinsics and `lens`, frame 3 a
// pinhole of its own; with `masks` every frame names masks/<name>.png.
fs::path write_nerfstudio_folder(const std::string& scratch, int count, const std::string& lens, bool masks,
                                 const std::string& extra_frame_keys = "") {
  const fs::path dir = test::scratch_dir(scratch);
  fs::create_directories(dir / "images");
  fs::create_directories(dir / "masks");
  std::string frames;
  for (int k = 0; k < count; ++k) {
    const int i = (k * 7) % count;
    if (k) frames += ",";
    frames += R"({"file_path":"images/)" + frame_name(i) + R"(.png","transform_matrix":[[1,0,0,)" +
              std::to_string(0.3 * i) + "],[0,1,0,0.1],[0,0,1,4],[0,0,0,1]]";
    if (i == 3) frames += R"(,"camera_model":"PINHOLE","k1":0,"k2":0,"p1":0,"p2":0,"fl_x":22)";
    if (masks) frames += R"(,"mask_path":"masks/)" + frame_name(i) + R"(.png")";
    frames += extra_frame_keys + "}";
    write_png(test::code_pattern(kWidth, kHeight, 3, i), dir / "images" / (frame_name(i) + ".png"));
    if (masks) write_png(left_mask(), dir / "masks" / (frame_name(i) + ".png"));
  }
  test::write_text(dir / "transforms.json", R"({"fl_x":20,"fl_y":21,"cx":12.5,"cy":9,"w":24,"h":18,)" + lens +
                                                R"(,"frames":[)" + frames + "]}");
  return dir;
}

const DatasetView& view_named(const Dataset& d, const std::string& name) {
  for (const auto* views : {&d.train, &d.test})
    for (const DatasetView& v : *views)
      if (v.name == name) return v;
  throw std::runtime_error("no view " + name);
}

TEST(DatasetNerfstudio, SplitsInNameOrderAndUndistortsOpenCvLenses) {
  const fs::path dir = write_nerfstudio_folder("nerfstudio_lens", 10, kLens, false);
  const Dataset d = load_dataset(dir);
  ASSERT_EQ(d.test.size(), 2u);  // every 8th in name order
  EXPECT_EQ(d.test[0].name, "frame_00");
  EXPECT_EQ(d.test[1].name, "frame_08");
  ASSERT_EQ(d.train.size(), 8u);
  for (std::size_t i = 1; i < d.train.size(); ++i) EXPECT_LT(d.train[i - 1].name, d.train[i].name);
  EXPECT_FALSE(d.points.has_value());

  // An OPENCV frame is the pinhole image cut to what the lens covers, as for COLMAP data.
  const LensDistortion lens{0.05, -0.01, 0.002, -0.003};
  const DatasetView& distorted = view_named(d, "frame_05");
  Camera pinhole = distorted.camera;
  pinhole.width = kWidth, pinhole.height = kHeight, pinhole.cx = 12.5f, pinhole.cy = 9.0f;
  const PixelRect covered = covered_region(pinhole, lens);
  const Image raw = read_image(dir / "images" / "frame_05.png");
  EXPECT_EQ(distorted.image.data, crop_image(undistort_image(raw, pinhole, lens, kWhite), covered).data);
  EXPECT_EQ(distorted.camera.width, covered.width);
  EXPECT_FLOAT_EQ(distorted.camera.fx, 20.0f);
  EXPECT_FLOAT_EQ(distorted.camera.fy, 21.0f);
  EXPECT_FLOAT_EQ(distorted.camera.cx, 12.5f - float(covered.x0));
  EXPECT_TRUE(distorted.mask.empty());
  // The frame that says PINHOLE (and its own focal length) is read as it is.
  const DatasetView& plain = view_named(d, "frame_03");
  EXPECT_EQ(plain.image.data, read_image(dir / "images" / "frame_03.png").data);
  EXPECT_FLOAT_EQ(plain.camera.fx, 22.0f);
  EXPECT_FLOAT_EQ(plain.camera.fy, 21.0f);

  DatasetOptions all;
  all.holdout_every = 0;
  const Dataset every = load_dataset(dir, all);
  EXPECT_EQ(every.train.size(), 10u);
  EXPECT_TRUE(every.test.empty());
}

TEST(DatasetNerfstudio, MasksFollowTheirImagesThroughUndistortionAndDownscale) {
  const fs::path pinhole_dir = write_nerfstudio_folder("nerfstudio_masks", 9, R"("camera_model":"PINHOLE")", true);
  DatasetOptions half;
  half.downscale = 2;
  const Dataset d = load_dataset(pinhole_dir, half);
  const DatasetView& view = view_named(d, "frame_04");
  ASSERT_EQ(view.mask.channels, 1);
  EXPECT_EQ(view.mask.width, view.image.width);
  EXPECT_EQ(view.mask.height, view.image.height);
  // write_png stores 8-bit codes: 0.6 is 153/255.
  Image stored = left_mask();
  for (int y = 0; y < kHeight; ++y) stored.at(16, y, 0) = 153.0f / 255.0f;
  EXPECT_EQ(view.mask.data, resample_area(stored, kWidth / 2, kHeight / 2).data);

  const fs::path lens_dir = write_nerfstudio_folder("nerfstudio_masks_lens", 9, kLens, true);
  const Dataset undistorted = load_dataset(lens_dir);
  const DatasetView& cut = view_named(undistorted, "frame_05");
  EXPECT_EQ(cut.mask.width, cut.image.width);
  EXPECT_EQ(cut.mask.height, cut.image.height);
  EXPECT_FLOAT_EQ(cut.mask.at(0, cut.mask.height / 2, 0), 1.0f);                  // kept
  EXPECT_FLOAT_EQ(cut.mask.at(cut.mask.width - 1, cut.mask.height / 2, 0), 0.0f);  // left out
}

TEST(DatasetNerfstudio, PointsFromPlyFilePath) {
  const fs::path dir = write_nerfstudio_folder("nerfstudio_points", 3, kLens, false);
  test::write_text(dir / "sparse_pc.ply", "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                                          "property float z\nproperty uint8 red\nproperty uint8 green\n"
                                          "property uint8 blue\nend_header\n1 2 3 255 0 0\n-1 0.5 2 0 255 0\n");
  std::string json = test::read_file(dir / "transforms.json");
  json.insert(1, R"("ply_file_path":"sparse_pc.ply",)");
  test::write_text(dir / "transforms.json", json);
  const Dataset d = load_dataset(dir);
  ASSERT_TRUE(d.points.has_value());
  EXPECT_EQ(d.points->positions, (std::vector<float>{1, 2, 3, -1, 0.5f, 2}));
  EXPECT_EQ(d.points->colors, (std::vector<float>{1, 0, 0, 0, 1, 0}));
  fs::remove(dir / "sparse_pc.ply");
  EXPECT_THROW(load_dataset(dir), InputError);
}

std::string load_error(const fs::path& dir) {
  try {
    load_dataset(dir);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(loaded)";
}

TEST(DatasetNerfstudio, ClearErrors) {
  const auto expect_error = [](const fs::path& dir, const std::string& expected) {
    const std::string message = load_error(dir);
    EXPECT_NE(message.find(expected), std::string::npos) << message;
  };
  expect_error(write_nerfstudio_folder("nerfstudio_fisheye", 3, R"("camera_model":"OPENCV_FISHEYE")", false),
               "transforms.json: \"camera_model\" is OPENCV_FISHEYE, which is not supported: PINHOLE, "
               "SIMPLE_PINHOLE and OPENCV are");
  expect_error(write_nerfstudio_folder("nerfstudio_k3", 3, std::string(kLens) + R"(,"k3":0.1)", false),
               "\"k3\" is not 0: OPENCV's k1, k2, p1, p2 are supported");
  expect_error(write_nerfstudio_folder("nerfstudio_pinhole_k1", 3, R"("camera_model":"PINHOLE","k1":0.1)", false),
               "camera model PINHOLE has no lens distortion, but k1, k2, p1 or p2 is not 0");

  const fs::path no_mask = write_nerfstudio_folder("nerfstudio_no_mask", 3, kLens, true);
  fs::remove(no_mask / "masks" / "frame_01.png");
  expect_error(no_mask, "masks/frame_01.png: mask image does not exist");
  const fs::path small_mask = write_nerfstudio_folder("nerfstudio_small_mask", 3, kLens, true);
  write_png(Image(8, 8, 1), small_mask / "masks" / "frame_02.png");
  expect_error(small_mask, "masks/frame_02.png: mask is 8 x 8 but its photo is 24 x 18");

  // The same photo listed twice would give two views one name (their outputs one file).
  const fs::path twice = write_nerfstudio_folder("nerfstudio_twice", 3, kLens, false);
  std::string json = test::read_file(twice / "transforms.json");
  json.replace(json.find("\"frames\":["), 10,
               R"("frames":[{"file_path":"images/frame_01.png","transform_matrix":[[1,0,0,0],[0,1,0,0],[0,0,1,4],[0,0,0,1]]},)");
  test::write_text(twice / "transforms.json", json);
  expect_error(twice, "would both be named 'images_frame_01'");
}

}  // namespace
}  // namespace splat
