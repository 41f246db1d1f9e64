#include "splat/data/colmap_model.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "tests/data/colmap_test_writer.hpp"
#include "splat/core/error.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;
using test::TestModel;

// One camera of every supported model, images listed out of name order with a quaternion
// that is not normalised, and points with tracks of varying length.
TestModel sample_model() {
  TestModel m;
  m.cameras = {
      {1, ColmapCameraModel::kSimplePinhole, 8, 6, {7.5, 4, 3}},
      {2, ColmapCameraModel::kPinhole, 8, 6, {7.5, 8.25, 4.1, 2.9}},
      {3, ColmapCameraModel::kSimpleRadial, 8, 6, {7.5, 4, 3, 0.05}},
      {4, ColmapCameraModel::kRadial, 10, 7, {9.5, 5, 3.5, 0.05, -0.01}},
      {7, ColmapCameraModel::kOpenCv, 8, 6, {7.5, 8, 4, 3, 0.05, -0.01, 0.002, -0.003}},
  };
  const char* names[] = {"c.png", "a.png", "e.png", "b.png", "d.png"};
  const std::uint32_t camera_ids[] = {1, 2, 3, 4, 7};
  for (int i = 0; i < 5; ++i) {
    ColmapImage image;
    image.id = std::uint32_t(10 + i);
    image.quaternion = test::axis_angle_quaternion(1, 2 - i, 0.5, 0.3 * i + 0.1);
    image.translation = {0.1 * i, -0.2, 3.0 + i};
    image.camera_id = camera_ids[i];
    image.name = names[i];
    m.images.push_back(image);
  }
  for (double& q : m.images[2].quaternion) q *= 2;  // COLMAP normalises on use
  for (int i = 0; i < 6; ++i)
    m.points.push_back({{0.125 * i, -1.0 / 3.0 * i, 2.0 + i},
                        {std::uint8_t(40 * i), std::uint8_t(255 - i), std::uint8_t(i * i)}});
  return m;
}

template <class F>
InputError input_error(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected InputError, got: " << e.what();
    return InputError("", "wrong exception");
  }
  ADD_FAILURE() << "expected InputError, nothing thrown";
  return InputError("", "nothing thrown");
}

std::vector<char> read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const fs::path& file, const std::vector<char>& bytes) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(bytes.size()));
}

void expect_matches(const ColmapModel& read, const TestModel& written) {
  ASSERT_EQ(read.cameras.size(), written.cameras.size());
  for (std::size_t i = 0; i < read.cameras.size(); ++i) {
    EXPECT_EQ(read.cameras[i].id, written.cameras[i].id);
    EXPECT_EQ(read.cameras[i].model, written.cameras[i].model);
    EXPECT_EQ(read.cameras[i].width, written.cameras[i].width);
    EXPECT_EQ(read.cameras[i].height, written.cameras[i].height);
    EXPECT_EQ(read.cameras[i].params, written.cameras[i].params);
  }
  ASSERT_EQ(read.images.size(), written.images.size());
  for (std::size_t i = 0; i < read.images.size(); ++i) {
    EXPECT_EQ(read.images[i].id, written.images[i].id);
    EXPECT_EQ(read.images[i].quaternion, written.images[i].quaternion);
    EXPECT_EQ(read.images[i].translation, written.images[i].translation);
    EXPECT_EQ(read.images[i].camera_id, written.images[i].camera_id);
    EXPECT_EQ(read.images[i].name, written.images[i].name);
  }
  ASSERT_EQ(read.point_positions.size(), written.points.size() * 3);
  ASSERT_EQ(read.point_colors.size(), written.points.size() * 3);
  for (std::size_t i = 0; i < written.points.size(); ++i)
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(read.point_positions[i * 3 + a], float(written.points[i].xyz[a]));
      EXPECT_EQ(read.point_colors[i * 3 + a], float(written.points[i].rgb[a]) / 255.0f);
    }
}

TEST(DatasetColmapModel, TextAndBinaryReadTheSame) {
  const fs::path dir = test::scratch_dir("colmap_model_forms");
  const TestModel model = sample_model();
  test::write_colmap_text(model, dir / "text");
  test::write_colmap_binary(model, dir / "binary");
  const ColmapModel text = read_colmap_model(dir / "text");
  const ColmapModel binary = read_colmap_model(dir / "binary");
  expect_matches(text, model);
  expect_matches(binary, model);
  EXPECT_EQ(text.cameras_file, dir / "text" / "cameras.txt");
  EXPECT_EQ(binary.points_file, dir / "binary" / "points3D.bin");
  ASSERT_NE(binary.find_camera(7), nullptr);
  EXPECT_EQ(binary.find_camera(7)->model, ColmapCameraModel::kOpenCv);
  EXPECT_EQ(binary.find_camera(5), nullptr);
}

TEST(DatasetColmapModel, PrefersBinaryWhenBothExist) {
  const fs::path dir = test::scratch_dir("colmap_model_prefers_binary");
  TestModel model = sample_model();
  test::write_colmap_text(model, dir);
  model.points.resize(2);
  model.cameras[0].params[0] = 11.0;
  test::write_colmap_binary(model, dir);
  const ColmapModel read = read_colmap_model(dir);
  EXPECT_EQ(read.point_positions.size(), 6u);
  EXPECT_EQ(read.cameras[0].params[0], 11.0);
  EXPECT_EQ(read.cameras_file.extension(), ".bin");
}

TEST(DatasetColmapModel, TextToleratesCommentsCrlfAndMissingPointLines) {
  const fs::path dir = test::scratch_dir("colmap_model_text_variants");
  test::write_text(dir / "cameras.txt", "# c\r\n\r\n1 PINHOLE 4 3 5 5 2 1.5\r\n");
  // Hand-written files often leave out the 2D-point lines; no image may be swallowed.
  test::write_text(dir / "images.txt",
                   "# i\n1 1 0 0 0 0 0 1 1 first name.png\n2 1 0 0 0 0 0 2 1 b.png\n"
                   "1.5 2.5 -1\n3 1 0 0 0 1e-1 0 2 1 c.png\n");
  test::write_text(dir / "points3D.txt", "1 1e-1 2 3 255 0 7 0.1 1 0\n");
  const ColmapModel m = read_colmap_model(dir);
  ASSERT_EQ(m.images.size(), 3u);
  EXPECT_EQ(m.images[0].name, "first name.png");
  EXPECT_EQ(m.images[1].name, "b.png");
  EXPECT_EQ(m.images[2].name, "c.png");
  EXPECT_DOUBLE_EQ(m.images[2].translation[0], 0.1);
  EXPECT_EQ(m.cameras[0].params, (std::vector<double>{5, 5, 2, 1.5}));
  ASSERT_EQ(m.point_positions.size(), 3u);
  EXPECT_FLOAT_EQ(m.point_positions[0], 0.1f);
  EXPECT_EQ(m.point_colors[0], 1.0f);
  EXPECT_FLOAT_EQ(m.point_colors[2], 7.0f / 255.0f);
}

TEST(DatasetColmapModel, UnsupportedModelsAreNamed) {
  const fs::path dir = test::scratch_dir("colmap_model_unsupported");
  test::write_colmap_text(sample_model(), dir);
  for (const std::string model : {"OPENCV_FISHEYE", "FULL_OPENCV", "FOV", "NOT_A_MODEL"}) {
    test::write_text(dir / "cameras.txt", "1 " + model + " 8 6 1 2 3 4 5 6 7 8\n");
    const InputError e = input_error([&] { read_colmap_model(dir); });
    EXPECT_EQ(e.file(), dir / "cameras.txt");
    EXPECT_NE(std::string(e.what()).find(model), std::string::npos) << e.what();
  }
  // In binary form the model is an id: 6 is FULL_OPENCV, 99 is no model at all.
  TestModel model = sample_model();
  model.cameras.resize(1);
  model.cameras[0].model = ColmapCameraModel(6);
  model.cameras[0].params.assign(12, 0.5);
  test::write_colmap_binary(model, dir);
  InputError e = input_error([&] { read_colmap_model(dir); });
  EXPECT_EQ(e.file(), dir / "cameras.bin");
  EXPECT_NE(std::string(e.what()).find("FULL_OPENCV"), std::string::npos) << e.what();
  model.cameras[0].model = ColmapCameraModel(99);
  test::write_colmap_binary(model, dir);
  e = input_error([&] { read_colmap_model(dir); });
  EXPECT_NE(std::string(e.what()).find("model id 99"), std::string::npos) << e.what();
}

TEST(DatasetColmapModel, MalformedTextIsReportedWithItsLine) {
  const fs::path dir = test::scratch_dir("colmap_model_bad_text");
  test::write_colmap_text(sample_model(), dir);
  const std::vector<std::pair<std::string, std::string>> bad_cameras = {
      {"1 PINHOLE 8 6 1 2 3\n", "parameters"},            // one parameter short
      {"1 PINHOLE 8 6 1 2 3 4 5\n", "parameters"},        // one too many
      {"1 PINHOLE 8 six 1 2 3 4\n", "height"},            // not a number
      {"1 PINHOLE 0 6 1 2 3 4\n", "size"},                // no pixels
      {"1 PINHOLE 8 6 -1 2 3 4\n", "focal"},              // negative focal length
      {"1 PINHOLE 8 6 nan 2 3 4\n", "non-finite"},
      {"1 PINHOLE 8 6 1 2 3 4\n1 PINHOLE 8 6 1 2 3 4\n", "twice"},
  };
  for (const auto& [text, expected] : bad_cameras) {
    test::write_text(dir / "cameras.txt", text);
    const InputError e = input_error([&] { read_colmap_cameras(dir / "cameras.txt"); });
    EXPECT_EQ(e.file(), dir / "cameras.txt");
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
  }
  test::write_text(dir / "images.txt", "1 1 0 0 0 0 0 1 1\n");  // no name
  EXPECT_EQ(input_error([&] { read_colmap_images(dir / "images.txt"); }).file(),
            dir / "images.txt");
  test::write_text(dir / "images.txt", "1 0 0 0 0 0 0 1 1 a.png\n");  // zero quaternion
  EXPECT_EQ(input_error([&] { read_colmap_images(dir / "images.txt"); }).file(),
            dir / "images.txt");
  std::vector<float> p, c;
  test::write_text(dir / "points3D.txt", "1 0 0 0 256 0 0 0\n");  // colour beyond 8 bits
  EXPECT_EQ(input_error([&] { read_colmap_points(dir / "points3D.txt", p, c); }).file(),
            dir / "points3D.txt");
}

TEST(DatasetColmapModel, TruncatedBinaryFilesFailCleanly) {
  const fs::path dir = test::scratch_dir("colmap_model_truncated");
  const TestModel model = sample_model();
  for (const std::string name : {"cameras.bin", "images.bin", "points3D.bin"}) {
    test::write_colmap_binary(model, dir);
    const std::vector<char> whole = read_bytes(dir / name);
    ASSERT_GT(whole.size(), 100u);
    // Every possible truncation, and one stray byte too many.
    for (std::size_t length = 0; length <= whole.size(); ++length) {
      std::vector<char> bytes(whole.begin(), whole.begin() + std::ptrdiff_t(length));
      if (length == whole.size()) bytes.push_back('\0');
      write_bytes(dir / name, bytes);
      const InputError e = input_error([&] { read_colmap_model(dir); });
      ASSERT_EQ(e.file(), dir / name) << "length " << length << ": " << e.what();
    }
  }
}

TEST(DatasetColmapModel, HugeCountsAreRejectedBeforeAllocating) {
  const fs::path dir = test::scratch_dir("colmap_model_huge_counts");
  const TestModel model = sample_model();
  const auto patch_u64 = [&](const std::string& name, std::size_t offset, std::uint64_t value) {
    test::write_colmap_binary(model, dir);
    std::vector<char> bytes = read_bytes(dir / name);
    ASSERT_LE(offset + 8, bytes.size());
    std::memcpy(bytes.data() + offset, &value, 8);
    write_bytes(dir / name, bytes);
    const InputError e = input_error([&] { read_colmap_model(dir); });
    EXPECT_EQ(e.file(), dir / name) << e.what();
    EXPECT_NE(std::string(e.what()).find("does not fit"), std::string::npos) << e.what();
  };
  for (std::uint64_t huge : {std::uint64_t(1) << 40, ~std::uint64_t(0)}) {
    patch_u64("cameras.bin", 0, huge);
    patch_u64("images.bin", 0, huge);
    patch_u64("points3D.bin", 0, huge);
    // The first image's 2D-point count: after count, id, pose, camera id and "c.png\0".
    patch_u64("images.bin", 8 + 4 + 56 + 4 + 6, huge);
    // The first point's track length: after count, id, xyz, rgb and error.
    patch_u64("points3D.bin", 8 + 8 + 24 + 3 + 8, huge);
  }
}

TEST(DatasetColmapModel, ImageWithUnknownCameraIsRejected) {
  const fs::path dir = test::scratch_dir("colmap_model_unknown_camera");
  TestModel model = sample_model();
  model.images[3].camera_id = 5;
  test::write_colmap_text(model, dir / "text");
  test::write_colmap_binary(model, dir / "binary");
  for (const fs::path& file : {dir / "text" / "images.txt", dir / "binary" / "images.bin"}) {
    const InputError e = input_error([&] { read_colmap_model(file.parent_path()); });
    EXPECT_EQ(e.file(), file);
    EXPECT_NE(std::string(e.what()).find("camera id 5"), std::string::npos) << e.what();
  }
}

TEST(DatasetColmapModel, EmptyPointCloudIsRejected) {
  const fs::path dir = test::scratch_dir("colmap_model_empty_points");
  TestModel model = sample_model();
  model.points.clear();
  test::write_colmap_text(model, dir / "text");
  test::write_colmap_binary(model, dir / "binary");
  for (const fs::path& file : {dir / "text" / "points3D.txt", dir / "binary" / "points3D.bin"}) {
    const InputError e = input_error([&] { read_colmap_model(file.parent_path()); });
    EXPECT_EQ(e.file(), file);
    EXPECT_NE(std::string(e.what()).find("empty"), std::string::npos) << e.what();
  }
}

TEST(DatasetColmapModel, MissingFilesAreNamed) {
  const fs::path dir = test::scratch_dir("colmap_model_missing");
  for (const std::string stem : {"cameras", "images", "points3D"}) {
    test::write_colmap_binary(sample_model(), dir);
    fs::remove(dir / (stem + ".bin"));
    const InputError e = input_error([&] { read_colmap_model(dir); });
    EXPECT_NE(std::string(e.what()).find(stem + ".bin or " + stem + ".txt"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace splat
