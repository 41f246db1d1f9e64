// The web model formats (.splat, .spz), the turn between their world conventions, and the
// format-by-extension entry points: round trips within each format's documented
// quantisation, images that survive, hand-made files of another writer's version, and bad
// input (one InputError naming the file and the problem).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "splat/core/activations.hpp"
#include "splat/core/error.hpp"
#include "splat/core/spherical_harmonics.hpp"
#include "splat/eval/metrics.hpp"
#include "splat/gaussians/axis_flip.hpp"
#include "splat/gaussians/gzip.hpp"
#include "splat/gaussians/model_file.hpp"
#include "splat/gaussians/ply_io.hpp"
#include "splat/gaussians/splat_file.hpp"
#include "splat/gaussians/spz_file.hpp"
#include "splat/raster/rasterizer.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

Image render(const GaussianModel& model, const Camera& camera) {
  RenderSettings settings;
  settings.for_backward = false;
  Rasterizer rasterizer;
  RenderResult result;
  rasterizer.render(model, camera, settings, result);
  return result.color;
}

// The camera that sees the half-turned world as `camera` sees the world: x_cam = R·F·x' + t.
Camera turned_camera(Camera camera) {
  camera.camera_from_world_rotation[1] = -camera.camera_from_world_rotation[1];
  camera.camera_from_world_rotation[2] = -camera.camera_from_world_rotation[2];
  return camera;
}

void write_bytes(const fs::path& file, const std::vector<unsigned char>& bytes) {
  std::ofstream out(file, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

void expect_input_error(const fs::path& file, const std::vector<std::string>& fragments) {
  try {
    read_gaussian_model(file);
    ADD_FAILURE() << file << " read without error";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(file.string(), 0), 0u) << message;
    for (const std::string& fragment : fragments) EXPECT_NE(message.find(fragment), std::string::npos) << message;
  }
}

// The rotation angle between two quaternions (w, x, y, z), in radians.
float rotation_angle(const Vec4<float>& a, const Vec4<float>& b) {
  const Vec4<float> ua = a / std::sqrt(glm::dot(a, a)), ub = b / std::sqrt(glm::dot(b, b));
  return 2.0f * std::acos(std::min(1.0f, std::abs(glm::dot(ua, ub))));
}

TEST(AxisFlip, TheTurnedModelSeenFromTheTurnedCameraIsTheSameImage) {
  const GaussianModel model = test::random_model(300, 3, 7);
  GaussianModel turned = model;
  turn_half_about_x(turned);
  for (const float distance : {3.0f, 4.5f}) {
    Camera camera = test::looking_at_origin(64, 48, distance);
    camera.camera_from_world_rotation = glm::mat3(glm::vec3(0.8f, 0.0f, -0.6f), glm::vec3(0, 1, 0),
                                                  glm::vec3(0.6f, 0.0f, 0.8f)) *
                                        camera.camera_from_world_rotation;  // off-axis: every SH band shows
    const Image plain = render(model, camera), seen_turned = render(turned, turned_camera(camera));
    double largest = 0;
    for (std::size_t i = 0; i < plain.data.size(); ++i)
      largest = std::max(largest, double(std::abs(plain.data[i] - seen_turned.data[i])));
    EXPECT_LT(largest, 1e-4) << "distance " << distance;
    // The turn changes the picture from the unturned camera: the test can fail.
    EXPECT_LT(psnr(plain, render(turned, camera)), 30.0);
  }
  GaussianModel twice = turned;
  turn_half_about_x(twice);
  EXPECT_EQ(twice.means, model.means);
  EXPECT_EQ(twice.quats, model.quats);
  EXPECT_EQ(twice.sh, model.sh);
}

TEST(SplatFile, RoundTripKeepsTheMeansExactlyAndTheRestWithinAByte) {
  const fs::path dir = test::scratch_dir("splat_file_round_trip");
  const GaussianModel model = test::random_model(500, 2, 11);
  write_gaussian_model(model, dir / "m.splat");
  EXPECT_EQ(fs::file_size(dir / "m.splat"), 500u * kSplatRecordBytes);
  const GaussianModel back = read_gaussian_model(dir / "m.splat");
  ASSERT_EQ(back.size(), model.size());
  EXPECT_EQ(back.sh_degree, 0);
  EXPECT_EQ(back.means, model.means);
  const std::size_t k = std::size_t(model.sh_coefficients());
  for (std::size_t i = 0; i < model.size(); ++i) {
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(back.log_scales[3 * i + a], model.log_scales[3 * i + a], 1e-6);
      const float colour = 0.5f + float(kShC0) * model.sh[i * k * 3 + a];
      if (colour > 0.0f && colour < 1.0f) {
        EXPECT_NEAR(0.5f + float(kShC0) * back.sh[3 * i + a], colour, 0.5f / 255 + 1e-6f);
      }
    }
    EXPECT_NEAR(back.opacity(i), model.opacity(i), 0.5f / 255 + 1e-6f);
    EXPECT_LT(rotation_angle(back.quat(i), model.quat(i)), 0.03f) << i;
  }
}

TEST(SpzFile, RoundTripStaysWithinTheQuantisationOfEachField) {
  const fs::path dir = test::scratch_dir("spz_file_round_trip");
  GaussianModel model = test::random_model(800, 3, 13);
  for (float& c : model.sh) c = std::clamp(c, -0.9f, 0.9f);  // the SH bytes hold [-1, 1]
  SpzWriteOptions exact;
  exact.sh1_bits = exact.sh_rest_bits = 8;
  write_gaussian_model(model, dir / "m.spz", exact);
  const GaussianModel back = read_gaussian_model(dir / "m.spz");
  ASSERT_EQ(back.size(), model.size());
  ASSERT_EQ(back.sh_degree, 3);
  const std::size_t k = 16;
  for (std::size_t i = 0; i < model.size(); ++i) {
    for (int a = 0; a < 3; ++a) {
      // The cube's half-size is 1: 16 fractional bits.
      EXPECT_NEAR(back.means[3 * i + a], model.means[3 * i + a], 0.5 / 65536 + 1e-7);
      EXPECT_NEAR(back.log_scales[3 * i + a], model.log_scales[3 * i + a], 0.5 / 16 + 1e-5);
      EXPECT_NEAR(back.sh[i * k * 3 + a], model.sh[i * k * 3 + a], 0.5 / (0.15 * 255) + 1e-5);
    }
    for (std::size_t j = 3; j < k * 3; ++j) EXPECT_NEAR(back.sh[i * k * 3 + j], model.sh[i * k * 3 + j], 0.5 / 128 + 1e-6);
    EXPECT_NEAR(back.opacity(i), model.opacity(i), 0.5f / 255 + 1e-6f);
    EXPECT_LT(rotation_angle(back.quat(i), model.quat(i)), 0.004f) << i;
  }
}

TEST(SpzFile, TheConformanceModelRendersWithin40DbOfThePlyAtTheDefaultQuantisation) {
  const test::ConformanceScene scene = test::load_conformance(200);
  const fs::path dir = test::scratch_dir("spz_file_conformance");
  write_gaussian_model(scene.model, dir / "m.spz");
  const GaussianModel back = read_gaussian_model(dir / "m.spz");
  EXPECT_LT(fs::file_size(dir / "m.spz") * 5, scene.model.size() * 62 * 4);  // < a fifth of the PLY
  for (std::size_t v = 0; v < scene.frames.size(); v += 4) {
    const double db = psnr(render(scene.model, scene.frames[v].camera), render(back, scene.frames[v].camera));
    EXPECT_GE(db, 40.0) << scene.frames[v].name;
  }
}

// Niantic's version 2 stores the rotation as (x, y, z) bytes with w ≥ 0; a file made by hand.
TEST(SpzFile, ReadsVersionTwo) {
  const fs::path dir = test::scratch_dir("spz_file_version_2");
  std::vector<unsigned char> bytes(16 + 9 + 1 + 3 + 3 + 3);
  const std::uint32_t header[3] = {kSpzMagic, 2, 1};
  std::memcpy(bytes.data(), header, 12);
  bytes[13] = 12;                                   // fractional bits; degree 0, no flags
  const std::int32_t x = 4096, y = -2048, z = 1024;  // (1, -0.5, 0.25) in the file's frame
  for (int b = 0; b < 3; ++b) {
    bytes[16 + b] = (x >> (8 * b)) & 0xff;
    bytes[19 + b] = (y >> (8 * b)) & 0xff;
    bytes[22 + b] = (z >> (8 * b)) & 0xff;
  }
  bytes[25] = 255;                       // alpha
  bytes[26] = bytes[27] = bytes[28] = 128;  // colour ≈ 0
  bytes[29] = bytes[30] = bytes[31] = 160;  // scales: 160/16 - 10 = 0
  bytes[32] = bytes[33] = bytes[34] = 128;  // rotation ≈ identity
  write_bytes(dir / "v2.spz", gzip(bytes));
  const GaussianModel model = read_gaussian_model(dir / "v2.spz");
  ASSERT_EQ(model.size(), 1u);
  EXPECT_FLOAT_EQ(model.means[0], 1.0f);  // turned into the PLY's frame: y and z change sign
  EXPECT_FLOAT_EQ(model.means[1], 0.5f);
  EXPECT_FLOAT_EQ(model.means[2], -0.25f);
  EXPECT_FLOAT_EQ(model.log_scales[1], 0.0f);
  EXPECT_GT(model.opacity(0), 0.995f);
  EXPECT_LT(rotation_angle(model.quat(0), {1, 0, 0, 0}), 0.02f);
}

TEST(SpzFile, RefusesCoordinatesBeyondTwentyFourBits) {
  GaussianModel model = test::random_model(3, 0, 1);
  model.means[4] = 9e6f;
  EXPECT_THROW(write_spz_file(model, test::scratch_dir("spz_far") / "m.spz"), ArgumentError);
}

// ---- Bad input -------------------------------------------------------------------------

class WebFormatBadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::scratch_dir(std::string("web_bad_") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
  }
  fs::path file_with(const std::string& name, const std::vector<unsigned char>& bytes) {
    write_bytes(dir_ / name, bytes);
    return dir_ / name;
  }
  // A valid .spz's inflated bytes (one Gaussian, degree 1).
  std::vector<unsigned char> spz_bytes() {
    write_spz_file(test::random_model(1, 1, 3), dir_ / "good.spz");
    std::ifstream in(dir_ / "good.spz", std::ios::binary);
    const std::vector<unsigned char> compressed{std::istreambuf_iterator<char>(in), {}};
    return gunzip(compressed, 1 << 20, dir_ / "good.spz");
  }
  fs::path dir_;
};

TEST_F(WebFormatBadInput, SplatFiles) {
  expect_input_error(dir_ / "absent.splat", {"does not exist"});
  expect_input_error(file_with("empty.splat", {}), {"empty"});
  expect_input_error(file_with("odd.splat", std::vector<unsigned char>(33)), {"33 bytes", "whole number"});
  std::vector<unsigned char> record(32, 0);
  float one = 1.0f, nan = std::nanf("");
  for (int a = 0; a < 3; ++a) std::memcpy(record.data() + 12 + 4 * a, &one, 4);
  record[28] = 255;  // w = 127/128
  EXPECT_NO_THROW(read_gaussian_model(file_with("good.splat", record)));
  std::vector<unsigned char> bad = record;
  std::memcpy(bad.data() + 4, &nan, 4);
  expect_input_error(file_with("nan.splat", bad), {"Gaussian 0", "mean", "not finite"});
  bad = record;
  std::memset(bad.data() + 16, 0, 4);
  expect_input_error(file_with("flat.splat", bad), {"Gaussian 0", "scale"});
  bad = record;
  std::memset(bad.data() + 28, 128, 4);
  expect_input_error(file_with("spin.splat", bad), {"Gaussian 0", "rotation of length zero"});
}

TEST_F(WebFormatBadInput, SpzFiles) {
  expect_input_error(file_with("plain.spz", spz_bytes()), {"version 3 that is not gzip-compressed"});
  expect_input_error(file_with("noise.spz", std::vector<unsigned char>(64, 7)), {"not valid gzip"});
  expect_input_error(file_with("short.spz", gzip(std::vector<unsigned char>(10, 0))), {"within its 16-byte header"});
  std::vector<unsigned char> bytes = spz_bytes();
  std::vector<unsigned char> bad = bytes;
  bad[0] = 'X';
  expect_input_error(file_with("magic.spz", gzip(bad)), {"NGSP"});
  for (const unsigned char version : {1, 4, 9}) {
    bad = bytes;
    bad[4] = version;
    expect_input_error(file_with("version.spz", gzip(bad)), {"version " + std::to_string(version)});
  }
  bad = bytes;
  bad[12] = 4;
  expect_input_error(file_with("degree.spz", gzip(bad)), {"SH degree 4"});
  bad = bytes;
  bad[14] = 2;
  expect_input_error(file_with("extensions.spz", gzip(bad)), {"extensions"});
  bad = bytes;
  bad[11] = 0x7f;  // about two thousand million Gaussians
  expect_input_error(file_with("count.spz", gzip(bad)), {"more than the 16777216"});
  bad = bytes;
  bad.pop_back();
  expect_input_error(file_with("truncated.spz", gzip(bad)), {"bytes; its header", "needs"});
  bad = bytes;
  bad.push_back(0);
  expect_input_error(file_with("long.spz", gzip(bad)), {"holds 46 bytes", "needs 45"});
  std::vector<unsigned char> compressed = gzip(bytes);
  compressed.resize(compressed.size() - 6);
  expect_input_error(file_with("cut.spz", compressed), {"ends early"});
  compressed = gzip(bytes);
  compressed.push_back(0);
  expect_input_error(file_with("trailing.spz", compressed), {"1 bytes follow the end of the gzip stream"});
}

TEST_F(WebFormatBadInput, PlyFilesOfOtherKindsSayWhatTheyAre) {
  test::write_text(dir_ / "compressed.ply",
                   "ply\nformat binary_little_endian 1.0\nelement chunk 0\nproperty float min_x\n"
                   "element vertex 0\nproperty uint packed_position\nend_header\n");
  expect_input_error(dir_ / "compressed.ply", {"compressed PLY", "splat-transform"});
  test::write_text(dir_ / "mesh.ply",
                   "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
                   "element face 0\nproperty list uchar int vertex_indices\nend_header\n");
  expect_input_error(dir_ / "mesh.ply", {"a mesh PLY", "not a 3DGS model"});
  test::write_text(dir_ / "points.ply",
                   "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
                   "property uchar red\nend_header\n");
  expect_input_error(dir_ / "points.ply", {"a point-cloud PLY"});
}

// splat-transform's PLY of a .spz carries the ±Inf logits Niantic's decoder gives opacity
// bytes 255 and 0; they read as our .spz reader reads those bytes. Any other Inf is refused.
TEST_F(WebFormatBadInput, InfiniteOpacityLogitsFromSpzDecodersReadAsTheirBytes) {
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
      "property float f_dc_0\nproperty float f_dc_1\nproperty float f_dc_2\nproperty float opacity\n"
      "property float scale_0\nproperty float scale_1\nproperty float scale_2\nproperty float rot_0\n"
      "property float rot_1\nproperty float rot_2\nproperty float rot_3\nend_header\n";
  test::write_text(dir_ / "inf.ply", header + "0 0 0 0 0 0 inf 0 0 0 1 0 0 0\n0 0 0 0 0 0 -inf 0 0 0 1 0 0 0\n");
  const GaussianModel model = read_gaussian_model(dir_ / "inf.ply");
  EXPECT_FLOAT_EQ(model.opacity(0), 254.5f / 255);
  EXPECT_FLOAT_EQ(model.opacity(1), 0.5f / 255);
  test::write_text(dir_ / "inf_scale.ply", header + "0 0 0 0 0 0 0 inf 0 0 1 0 0 0\n0 0 0 0 0 0 0 0 0 0 1 0 0 0\n");
  expect_input_error(dir_ / "inf_scale.ply", {"vertex 0", "'scale_0'", "Inf"});
}

// Version 4 (splat-transform's default) keeps its header out of the gzip layer.
TEST_F(WebFormatBadInput, SpzVersionFourSaysHowToWriteVersionThree) {
  std::vector<unsigned char> bytes(32, 0);
  const std::uint32_t header[2] = {kSpzMagic, 4};
  std::memcpy(bytes.data(), header, 8);
  expect_input_error(file_with("v4.spz", bytes), {".spz version 4", "--spz-version 3"});
}

TEST_F(WebFormatBadInput, OtherExtensions) {
  test::write_text(dir_ / "model.obj", "v 0 0 0\n");
  expect_input_error(dir_ / "model.obj", {"not a Gaussian model file", ".spz"});
  EXPECT_THROW(write_gaussian_model(test::random_model(1, 0, 1), dir_ / "model.obj"), ArgumentError);
  EXPECT_FALSE(fs::exists(dir_ / "model.obj.tmp"));
}

}  // namespace
}  // namespace splat
