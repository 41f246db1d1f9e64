#include "splat/data/transforms_json.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "splat/core/error.hpp"
#include "splat/data/image_io.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

constexpr float kConformanceTanHalfFov = 0.36f;  // tan(0.6911112070083618 / 2)
const std::string kIdentity = "[[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]";

fs::path conformance_file() { return test::conformance_dir() / "transforms_test.json"; }

// Writes `text` as `name` in a fresh folder for `test_name` and returns its path.
fs::path write_json(const std::string& test_name, const std::string& name,
                    const std::string& text) {
  const fs::path file = test::scratch_dir(test_name) / name;
  test::write_text(file, text);
  return file;
}

std::string one_frame(const std::string& extra_file_level, const std::string& extra_frame = "") {
  return "{" + extra_file_level + (extra_file_level.empty() ? "" : ",") +
         R"("frames":[{"file_path":"./images/a",)" + extra_frame +
         (extra_frame.empty() ? "" : ",") + R"("transform_matrix":)" + kIdentity + "}]}";
}

void expect_orthonormal(const glm::mat3& r) {
  const glm::mat3 rtr = glm::transpose(r) * r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(rtr[i][j], i == j ? 1.0f : 0.0f, 1e-5f);
  EXPECT_NEAR(glm::determinant(r), 1.0f, 1e-5f);
}

TEST(TransformsJson, ConformanceFramesAndNames) {
  const auto frames = load_transforms(conformance_file());
  ASSERT_EQ(frames.size(), 13u);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(frames[i].name, "r_" + std::to_string(8 * i));
    EXPECT_EQ(frames[i].image_path,
              (conformance_file().parent_path() / "test" / (frames[i].name + ".png"))
                  .lexically_normal());
  }
}

TEST(TransformsJson, ConformanceIntrinsicsAt400) {
  const auto frames = load_transforms(conformance_file(), {400, 400});
  for (const CameraFrame& f : frames) {
    EXPECT_EQ(f.camera.width, 400);
    EXPECT_EQ(f.camera.height, 400);
    EXPECT_NEAR(f.camera.fx, 200.0f / kConformanceTanHalfFov, 1e-3f);
    EXPECT_NEAR(f.camera.fy, 200.0f / kConformanceTanHalfFov, 1e-3f);
    EXPECT_FLOAT_EQ(f.camera.cx, 200.0f);
    EXPECT_FLOAT_EQ(f.camera.cy, 200.0f);
    EXPECT_NEAR(f.camera.tan_half_fov_x(), kConformanceTanHalfFov, 1e-6f);
  }
}

TEST(TransformsJson, ConformanceDefaultsTo800WithoutImages) {
  // conformance/test/ holds no images, and the file has no "w"/"h".
  ASSERT_FALSE(fs::exists(conformance_file().parent_path() / "test" / "r_0.png"));
  const auto frames = load_transforms(conformance_file());
  EXPECT_EQ(frames[0].camera.width, 800);
  EXPECT_EQ(frames[0].camera.height, 800);
  EXPECT_NEAR(frames[0].camera.fx, 400.0f / kConformanceTanHalfFov, 2e-3f);
  EXPECT_FLOAT_EQ(frames[0].camera.cx, 400.0f);
}

TEST(TransformsJson, ConformanceExtrinsicsFollowTheConvention) {
  const auto frames = load_transforms(conformance_file(), {400, 400});
  std::ifstream in(conformance_file());
  const nlohmann::json root = nlohmann::json::parse(in);
  ASSERT_EQ(root["frames"].size(), frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    SCOPED_TRACE(frames[i].name);
    const Camera& cam = frames[i].camera;
    const auto& m = root["frames"][i]["transform_matrix"];
    expect_orthonormal(cam.camera_from_world_rotation);
    // The camera sits at the matrix's translation column.
    const glm::vec3 center = cam.center_in_world();
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(center[a], m[a][3].get<float>(), 1e-4f);
    // It looks down the GL -z axis: camera +z in world is minus the matrix's third column,
    // and camera +y (image down) is minus its second (GL y is up).
    const glm::mat3 world_from_camera = glm::transpose(cam.camera_from_world_rotation);
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(world_from_camera[0][a], m[a][0].get<float>(), 1e-5f);
      EXPECT_NEAR(world_from_camera[1][a], -m[a][1].get<float>(), 1e-5f);
      EXPECT_NEAR(world_from_camera[2][a], -m[a][2].get<float>(), 1e-5f);
    }
    // The lego sits at the world origin: in front of every camera, and inside the image,
    // close to its centre (every test view aims at it).
    const glm::vec3 origin = cam.camera_from_world(glm::vec3(0.0f));
    ASSERT_GT(origin.z, 0.0f);
    const float u = cam.fx * origin.x / origin.z + cam.cx;
    const float v = cam.fy * origin.y / origin.z + cam.cy;
    EXPECT_NEAR(u, 200.0f, 40.0f);
    EXPECT_NEAR(v, 200.0f, 40.0f);
  }
}

TEST(TransformsJson, IdentityGlCameraLooksDownMinusZWithYUp) {
  const fs::path file =
      write_json("transforms_identity", "t.json", one_frame(R"("camera_angle_x":0.8)", R"("w":100,"h":80)"));
  const Camera cam = load_transforms(file).at(0).camera;
  const glm::vec3 ahead = cam.camera_from_world({0.0f, 0.0f, -5.0f});
  EXPECT_NEAR(ahead.x, 0.0f, 1e-6f);
  EXPECT_NEAR(ahead.y, 0.0f, 1e-6f);
  EXPECT_NEAR(ahead.z, 5.0f, 1e-6f);
  const glm::vec3 up = cam.camera_from_world({0.0f, 1.0f, -5.0f});
  EXPECT_LT(up.y, 0.0f);  // world up is image up, which is camera -y
  EXPECT_NEAR(up.y, -1.0f, 1e-6f);
  const glm::vec3 right = cam.camera_from_world({1.0f, 0.0f, -5.0f});
  EXPECT_NEAR(right.x, 1.0f, 1e-6f);  // right stays right
  // Projected: the point ahead lands on the centre, the one above it above the centre.
  EXPECT_FLOAT_EQ(cam.fx * ahead.x / ahead.z + cam.cx, 50.0f);
  EXPECT_FLOAT_EQ(cam.fy * ahead.y / ahead.z + cam.cy, 40.0f);
  EXPECT_LT(cam.fy * up.y / up.z + cam.cy, 40.0f);
  EXPECT_FLOAT_EQ(cam.fx, float(50.0 / std::tan(0.4)));
  EXPECT_FLOAT_EQ(cam.fy, cam.fx);
}

TEST(TransformsJson, CameraAngleYSetsFy) {
  const fs::path file = write_json("transforms_angle_y", "t.json",
                                   one_frame(R"("camera_angle_x":0.8,"camera_angle_y":0.6,"w":100,"h":80)"));
  const Camera cam = load_transforms(file).at(0).camera;
  EXPECT_FLOAT_EQ(cam.fx, float(50.0 / std::tan(0.4)));
  EXPECT_FLOAT_EQ(cam.fy, float(40.0 / std::tan(0.3)));
}

TEST(TransformsJson, FocalLengthsAtFileLevel) {
  const fs::path file = write_json(
      "transforms_fl_file", "t.json",
      one_frame(R"("fl_x":300,"fl_y":310,"cx":320.5,"cy":240.25,"w":640,"h":480)"));
  const Camera cam = load_transforms(file).at(0).camera;
  EXPECT_FLOAT_EQ(cam.fx, 300.0f);
  EXPECT_FLOAT_EQ(cam.fy, 310.0f);
  EXPECT_FLOAT_EQ(cam.cx, 320.5f);
  EXPECT_FLOAT_EQ(cam.cy, 240.25f);
  EXPECT_EQ(cam.width, 640);
  EXPECT_EQ(cam.height, 480);
}

TEST(TransformsJson, FlYAndPrincipalPointDefault) {
  const fs::path file =
      write_json("transforms_fl_defaults", "t.json", one_frame(R"("fl_x":300,"w":640,"h":480)"));
  const Camera cam = load_transforms(file).at(0).camera;
  EXPECT_FLOAT_EQ(cam.fy, 300.0f);
  EXPECT_FLOAT_EQ(cam.cx, 320.0f);
  EXPECT_FLOAT_EQ(cam.cy, 240.0f);
}

TEST(TransformsJson, FlXWinsOverCameraAngleX) {
  const fs::path file = write_json("transforms_fl_wins", "t.json",
                                   one_frame(R"("camera_angle_x":0.8,"fl_x":300,"w":640,"h":480)"));
  EXPECT_FLOAT_EQ(load_transforms(file).at(0).camera.fx, 300.0f);
}

TEST(TransformsJson, PerFrameIntrinsicsOverrideFileLevel) {
  const std::string text = R"({"fl_x":300,"w":640,"h":480,"frames":[
      {"file_path":"a","transform_matrix":)" + kIdentity + R"(},
      {"file_path":"b","fl_x":500,"fl_y":510,"cx":600,"cy":350,"w":1280,"h":720,
       "transform_matrix":)" + kIdentity + R"(},
      {"file_path":"c","h":600,"transform_matrix":)" + kIdentity + R"(}]})";
  const auto frames = load_transforms(write_json("transforms_per_frame", "t.json", text));
  ASSERT_EQ(frames.size(), 3u);
  const Camera& a = frames[0].camera;
  EXPECT_EQ(a.width, 640);
  EXPECT_EQ(a.height, 480);
  EXPECT_FLOAT_EQ(a.fx, 300.0f);
  EXPECT_FLOAT_EQ(a.cx, 320.0f);
  const Camera& b = frames[1].camera;
  EXPECT_EQ(b.width, 1280);
  EXPECT_EQ(b.height, 720);
  EXPECT_FLOAT_EQ(b.fx, 500.0f);
  EXPECT_FLOAT_EQ(b.fy, 510.0f);
  EXPECT_FLOAT_EQ(b.cx, 600.0f);
  EXPECT_FLOAT_EQ(b.cy, 350.0f);
  // Key by key: the frame's "h" with the file's "w".
  const Camera& c = frames[2].camera;
  EXPECT_EQ(c.width, 640);
  EXPECT_EQ(c.height, 600);
  EXPECT_FLOAT_EQ(c.cy, 300.0f);
}

TEST(TransformsJson, NativeSizeFromTheFirstImage) {
  const fs::path dir = test::scratch_dir("transforms_native_size");
  fs::create_directories(dir / "images");
  write_png(Image(64, 48, 4, 0.5f), dir / "images" / "a.png");
  for (const std::string path : {"./images/a", "images/a.png"}) {
    SCOPED_TRACE(path);
    test::write_text(dir / "t.json", R"({"camera_angle_x":0.8,"frames":[{"file_path":")" +
                                         path + R"(","transform_matrix":)" + kIdentity + "}]}");
    const auto frames = load_transforms(dir / "t.json");
    EXPECT_EQ(frames[0].name, "a");
    EXPECT_EQ(frames[0].image_path, dir / "images" / "a.png");
    EXPECT_EQ(frames[0].camera.width, 64);
    EXPECT_EQ(frames[0].camera.height, 48);
    EXPECT_FLOAT_EQ(frames[0].camera.cx, 32.0f);
    EXPECT_FLOAT_EQ(frames[0].camera.cy, 24.0f);
    EXPECT_FLOAT_EQ(frames[0].camera.fx, float(32.0 / std::tan(0.4)));
  }
}

TEST(TransformsJson, LegoTrainingSetTakesItsSizeFromImages) {
  SPLAT_SKIP_WITHOUT_BENCHMARK_DATA("lego400");
  const auto frames = load_transforms(test::benchmark_data_dir() / "lego400" /
                                      "transforms_train.json");
  ASSERT_EQ(frames.size(), 87u);
  EXPECT_EQ(frames[0].name, "r_1");
  EXPECT_TRUE(fs::exists(frames[0].image_path)) << frames[0].image_path;
  EXPECT_EQ(frames[0].camera.width, 400);
  EXPECT_EQ(frames[0].camera.height, 400);
  EXPECT_NEAR(frames[0].camera.fx, 200.0f / kConformanceTanHalfFov, 1e-3f);
}

TEST(TransformsJson, DefaultsTo800x800) {
  const fs::path file = write_json("transforms_default", "t.json", one_frame(R"("fl_x":1000)"));
  const Camera cam = load_transforms(file).at(0).camera;
  EXPECT_EQ(cam.width, 800);
  EXPECT_EQ(cam.height, 800);
  EXPECT_FLOAT_EQ(cam.cx, 400.0f);
}

TEST(TransformsJson, ResizingScalesIntrinsicsNotPose) {
  const std::string text = R"({"fl_x":300,"fl_y":320,"cx":330,"cy":250,"w":640,"h":480,
      "frames":[{"file_path":"a","transform_matrix":[[0,0,1,4],[1,0,0,5],[0,1,0,6],[0,0,0,1]]}]})";
  const fs::path file = write_json("transforms_resize", "t.json", text);
  const Camera native = load_transforms(file).at(0).camera;
  const Camera half = load_transforms(file, {320, 120}).at(0).camera;
  EXPECT_EQ(half.width, 320);
  EXPECT_EQ(half.height, 120);
  EXPECT_FLOAT_EQ(half.fx, 150.0f);
  EXPECT_FLOAT_EQ(half.cx, 165.0f);
  EXPECT_FLOAT_EQ(half.fy, 80.0f);
  EXPECT_FLOAT_EQ(half.cy, 62.5f);
  EXPECT_EQ(half.camera_from_world_rotation, native.camera_from_world_rotation);
  EXPECT_EQ(half.camera_from_world_translation, native.camera_from_world_translation);
  EXPECT_NEAR(native.center_in_world().x, 4.0f, 1e-6f);
  EXPECT_NEAR(native.center_in_world().y, 5.0f, 1e-6f);
  EXPECT_NEAR(native.center_in_world().z, 6.0f, 1e-6f);
}

TEST(TransformsJson, OutputSizeNeedsBothSides) {
  const fs::path file = write_json("transforms_one_side", "t.json", one_frame(R"("fl_x":300)"));
  EXPECT_THROW(load_transforms(file, {400, 0}), ArgumentError);
  EXPECT_THROW(load_transforms(file, {0, 400}), ArgumentError);
  EXPECT_THROW(load_transforms(file, {-400, 400}), ArgumentError);
}

std::string input_error_message(const fs::path& file) {
  try {
    load_transforms(file);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), file);
    return e.what();
  }
  ADD_FAILURE() << "no InputError for " << file;
  return "";
}

TEST(TransformsJson, MissingFileAndFolderNameThemselves) {
  const fs::path dir = test::scratch_dir("transforms_missing");
  EXPECT_NE(input_error_message(dir / "absent.json").find("absent.json"), std::string::npos);
  fs::create_directories(dir / "folder.json");
  EXPECT_NE(input_error_message(dir / "folder.json").find("folder.json"), std::string::npos);
}

TEST(TransformsJson, UnreadableFirstImageNamesBothFiles) {
  const fs::path dir = test::scratch_dir("transforms_bad_image");
  fs::create_directories(dir / "images");
  test::write_text(dir / "images" / "a.png", "not a png");
  test::write_text(dir / "t.json", one_frame(R"("fl_x":300)"));
  const std::string message = input_error_message(dir / "t.json");
  EXPECT_NE(message.find("t.json"), std::string::npos) << message;
  EXPECT_NE(message.find("a.png"), std::string::npos) << message;
}

struct BadInput {
  const char* label;
  std::string text;
  const char* expected;  // a fragment of the message that names the problem
};

std::string matrix_frame(const std::string& matrix) {
  return R"({"camera_angle_x":0.8,"w":10,"h":10,"frames":[{"file_path":"a","transform_matrix":)" +
         matrix + "}]}";
}

TEST(TransformsJson, BadInputsThrowInputErrorNamingTheFile) {
  const std::vector<BadInput> cases = {
      {"syntax", R"({"frames": [)", "parse error"},
      {"trailing_comma", R"({"camera_angle_x": 0.8,})", "malformed JSON"},
      {"nan_literal", matrix_frame("[[NaN,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]"), "malformed JSON"},
      {"top_level_array", "[]", "top level"},
      {"no_frames", R"({"camera_angle_x":0.8})", "missing \"frames\""},
      {"frames_not_array", R"({"camera_angle_x":0.8,"frames":{}})", "\"frames\""},
      {"frames_empty", R"({"camera_angle_x":0.8,"frames":[]})", "empty"},
      {"frame_not_object", R"({"camera_angle_x":0.8,"frames":[1]})", "frames[0]"},
      {"no_file_path", R"({"camera_angle_x":0.8,"frames":[{"transform_matrix":)" + kIdentity + "}]}",
       "file_path"},
      {"file_path_number", R"({"camera_angle_x":0.8,"frames":[{"file_path":5,"transform_matrix":)" +
                               kIdentity + "}]}",
       "file_path"},
      {"file_path_empty", R"({"camera_angle_x":0.8,"frames":[{"file_path":"","transform_matrix":)" +
                              kIdentity + "}]}",
       "file_path"},
      {"file_path_folder", R"({"camera_angle_x":0.8,"frames":[{"file_path":"./","transform_matrix":)" +
                               kIdentity + "}]}",
       "file_path"},
      {"no_matrix", R"({"camera_angle_x":0.8,"frames":[{"file_path":"a"}]})", "transform_matrix"},
      {"matrix_3x4", matrix_frame("[[1,0,0,0],[0,1,0,0],[0,0,1,0]]"), "4x4"},
      {"matrix_row_of_3", matrix_frame("[[1,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]"), "4x4"},
      {"matrix_string", matrix_frame(R"([[1,0,0,"x"],[0,1,0,0],[0,0,1,0],[0,0,0,1]])"), "4x4"},
      {"matrix_flat", matrix_frame("[1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1]"), "4x4"},
      {"matrix_overflow", matrix_frame("[[1,0,0,1e999],[0,1,0,0],[0,0,1,0],[0,0,0,1]]"), ""},
      {"matrix_scaled", matrix_frame("[[2,0,0,0],[0,2,0,0],[0,0,2,0],[0,0,0,1]]"), "rigid"},
      {"matrix_mirrored", matrix_frame("[[-1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]"), "rigid"},
      {"matrix_projective", matrix_frame("[[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,1,1]]"), "rigid"},
      {"no_intrinsics", R"({"w":10,"h":10,"frames":[{"file_path":"a","transform_matrix":)" +
                            kIdentity + "}]}",
       "intrinsics"},
      {"angle_zero", one_frame(R"("camera_angle_x":0)"), "camera_angle_x"},
      {"angle_negative", one_frame(R"("camera_angle_x":-0.5)"), "camera_angle_x"},
      {"angle_over_pi", one_frame(R"("camera_angle_x":3.5)"), "camera_angle_x"},
      {"angle_tiny", one_frame(R"("camera_angle_x":1e-9)"), "focal"},
      {"angle_string", one_frame(R"("camera_angle_x":"wide")"), "camera_angle_x"},
      {"angle_y_bad", one_frame(R"("camera_angle_x":0.8,"camera_angle_y":0)"), "camera_angle_y"},
      {"fl_zero", one_frame(R"("fl_x":0)"), "focal"},
      {"fl_negative", one_frame(R"("fl_x":-300)"), "focal"},
      {"fl_absurd", one_frame(R"("fl_x":1e12)"), "focal"},
      {"fl_y_negative", one_frame(R"("fl_x":300,"fl_y":-1)"), "fl_y"},
      {"fl_null", one_frame(R"("fl_x":null)"), "fl_x"},
      {"frame_fl_bad", one_frame(R"("fl_x":300)", R"("fl_x":"long")"), "frames[0]: \"fl_x\""},
      {"w_zero", one_frame(R"("fl_x":300,"w":0,"h":10)"), "\"w\" must"},
      {"w_negative", one_frame(R"("fl_x":300,"w":-5,"h":10)"), "\"w\" must"},
      {"w_fraction", one_frame(R"("fl_x":300,"w":100.5,"h":10)"), "\"w\" must"},
      {"h_huge", one_frame(R"("fl_x":300,"w":10,"h":1e9)"), "\"h\" must"},
      {"w_without_h", one_frame(R"("fl_x":300,"w":10)"), "without"},
      {"frame_h_without_w", one_frame(R"("fl_x":300)", R"("h":10)"), "without"},
      {"cx_string", one_frame(R"("fl_x":300,"cx":"middle")"), "cx"},
      {"cy_bool", one_frame(R"("fl_x":300,"cy":true)"), "cy"},
  };
  const fs::path dir = test::scratch_dir("transforms_bad_inputs");
  for (const BadInput& c : cases) {
    SCOPED_TRACE(c.label);
    const fs::path file = dir / (std::string("bad_") + c.label + ".json");
    test::write_text(file, c.text);
    const std::string message = input_error_message(file);
    EXPECT_NE(message.find(file.filename().string()), std::string::npos) << message;
    EXPECT_NE(message.find(c.expected), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace splat
