// Bad scene inputs each give an InputError that names the file at fault (and the key).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "tests/cli_support.hpp"
#include "splat/raytrace/gltf_mesh.hpp"
#include "splat/raytrace/scene_spec.hpp"
#include "tests/raytrace/scene_test_files.hpp"
#include "splat/core/error.hpp"
#include "tests/test_support.hpp"

namespace splat::raytrace {
namespace {

namespace fs = std::filesystem;

// The error's message, or "" when nothing was thrown.
template <class F>
std::string input_error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

void expect_contains(const std::string& text, const std::string& part) {
  EXPECT_NE(text.find(part), std::string::npos) << "\"" << text << "\" lacks \"" << part << "\"";
}

TEST(SceneErrors, MissingGltfNamesTheFile) {
  const fs::path dir = test::scratch_dir("scene_err_missing");
  test::write_json(dir / "scene.json", test::tiny_spec("models/nothing.gltf"));
  const SceneSpec spec = load_scene_spec(dir / "scene.json");
  expect_contains(input_error_of([&] { load_gltf_mesh(spec.gltf); }), "nothing.gltf");
}

TEST(SceneErrors, MalformedGltfNamesTheFile) {
  const fs::path dir = test::scratch_dir("scene_err_malformed");
  test::write_text(dir / "broken.gltf", "{ \"asset\": { \"version\": ");
  expect_contains(input_error_of([&] { load_gltf_mesh(dir / "broken.gltf"); }), "broken.gltf");
  // Valid JSON but a buffer that is not there.
  test::write_test_gltf(dir / "lost.gltf", test::plane_mesh(1, 0));
  fs::remove(dir / "lost.bin");
  expect_contains(input_error_of([&] { load_gltf_mesh(dir / "lost.gltf"); }), "lost.gltf");
}

TEST(SceneErrors, TextureThatDoesNotLoadNamesTheFile) {
  const fs::path dir = test::scratch_dir("scene_err_texture");
  test::write_text(dir / "bad.png", "this is not a PNG");
  test::write_test_gltf(dir / "textured.gltf", test::plane_mesh(1, 0), "bad.png");
  const std::string message = input_error_of([&] { load_gltf_mesh(dir / "textured.gltf"); });
  expect_contains(message, "textured.gltf");
  expect_contains(message, "bad.png");
  // An image file that is not there at all.
  test::write_test_gltf(dir / "lost_image.gltf", test::plane_mesh(1, 0), "nowhere.png");
  const std::string lost = input_error_of([&] { load_gltf_mesh(dir / "lost_image.gltf"); });
  expect_contains(lost, "lost_image.gltf");
  expect_contains(lost, "nowhere.png");
}

TEST(SceneErrors, SpecProblemsNameTheFileAndTheKey) {
  const fs::path dir = test::scratch_dir("scene_err_spec");
  struct Case {
    const char* name;
    void (*edit)(nlohmann::json&);
    const char* key;
  };
  const Case cases[] = {
      {"unknown_top", [](nlohmann::json& s) { s["lightz"] = 1; }, "lightz"},
      {"unknown_camera", [](nlohmann::json& s) { s["cameras"]["raduis"] = 4; }, "cameras.raduis"},
      {"unknown_light", [](nlohmann::json& s) { s["lights"][1]["range"] = 4; }, "lights[1].range"},
      {"negative_radius", [](nlohmann::json& s) { s["cameras"]["radius"] = -1; }, "cameras.radius"},
      {"zero_width", [](nlohmann::json& s) { s["cameras"]["width"] = 0; }, "cameras.width"},
      {"elevation_high", [](nlohmann::json& s) { s["cameras"]["elevation_deg"] = {10, 95}; },
       "cameras.elevation_deg"},
      {"elevation_order", [](nlohmann::json& s) { s["cameras"]["elevation_deg"] = {60, 10}; },
       "cameras.elevation_deg"},
      {"fov", [](nlohmann::json& s) { s["cameras"]["fov_deg"] = 180; }, "cameras.fov_deg"},
      {"no_train", [](nlohmann::json& s) { s["cameras"]["train"] = 0; }, "cameras.train"},
      {"spp", [](nlohmann::json& s) { s["samples_per_pixel"] = 0; }, "samples_per_pixel"},
      {"background", [](nlohmann::json& s) { s["background"] = {1, 2, 0}; }, "background"},
      {"light_type", [](nlohmann::json& s) { s["lights"][0]["type"] = "spot"; }, "lights[0].type"},
      {"missing_gltf", [](nlohmann::json& s) { s.erase("gltf"); }, "gltf"},
      // Values Embree cannot trace (a radius of 1e19 tripped its assertion) or that overflow
      // a float (a light of 1e39).
      {"huge_radius", [](nlohmann::json& s) { s["cameras"]["radius"] = 1e19; }, "cameras.radius"},
      {"huge_target", [](nlohmann::json& s) { s["cameras"]["target"] = {0, 1e19, 0}; }, "cameras.target"},
      {"huge_intensity", [](nlohmann::json& s) { s["lights"][0]["intensity"] = 1e39; }, "lights[0].intensity"},
      {"huge_light_position", [](nlohmann::json& s) { s["lights"][1]["position"] = {1e7, 0, 0}; },
       "lights[1].position"},
  };
  for (const Case& c : cases) {
    nlohmann::json spec = test::tiny_spec("x.gltf");
    c.edit(spec);
    const fs::path file = dir / (std::string(c.name) + ".json");
    test::write_json(file, spec);
    const std::string message = input_error_of([&] { load_scene_spec(file); });
    SCOPED_TRACE(c.name);
    expect_contains(message, file.filename().string());
    expect_contains(message, std::string("\"") + c.key + "\"");
  }
  test::write_text(dir / "not_json.json", "{ \"gltf\": ");
  expect_contains(input_error_of([&] { load_scene_spec(dir / "not_json.json"); }), "not_json.json");
  // The tiny spec itself is fine, comments allowed.
  test::write_text(dir / "ok.json", "// a comment\n" + test::tiny_spec("x.gltf").dump());
  EXPECT_EQ(input_error_of([&] { load_scene_spec(dir / "ok.json"); }), "");
}

// Damaged glTF files: each is an InputError naming the file and what is wrong, never
// accepted (as NaN positions, a zero quaternion or a 3-number matrix were) and never a read
// outside the buffer (as an offset that wraps the sum around could give).
TEST(SceneErrors, DamagedGltfIsRefusedNamingTheFile) {
  const fs::path dir = test::scratch_dir("scene_err_gltf_damage");
  const fs::path good = dir / "good.gltf";
  test::write_test_gltf(good, test::cube_mesh(0.5f));
  EXPECT_EQ(input_error_of([&] { load_gltf_mesh(good); }), "");
  const nlohmann::json original = nlohmann::json::parse(test::read_file(good));
  const std::string bin = test::read_file(dir / "good.bin");
  struct Case {
    const char* name;
    void (*edit)(nlohmann::json&, std::string&);
    const char* expected;
  };
  const Case cases[] = {
      {"nan_position",
       [](nlohmann::json&, std::string& b) {
         const float nan = std::nanf("");
         std::memcpy(b.data(), &nan, 4);
       },
       "POSITION"},
      {"inf_position",
       [](nlohmann::json&, std::string& b) {
         const float inf = INFINITY;
         std::memcpy(b.data() + 4, &inf, 4);
       },
       "POSITION"},
      {"negative_accessor_offset", [](nlohmann::json& g, std::string&) { g["accessors"][0]["byteOffset"] = -64; },
       "accessors[0].byteOffset"},
      {"huge_accessor_offset",
       [](nlohmann::json& g, std::string&) { g["accessors"][0]["byteOffset"] = 18446744073709551552.0; }, ""},
      {"matrix_of_three", [](nlohmann::json& g, std::string&) { g["nodes"][0]["matrix"] = {1, 0, 0}; }, "matrix"},
      {"zero_quaternion", [](nlohmann::json& g, std::string&) { g["nodes"][0]["rotation"] = {0, 0, 0, 0}; },
       "rotation"},
      {"huge_scale", [](nlohmann::json& g, std::string&) { g["nodes"][0]["scale"] = {1e9, 1, 1}; }, "scale"},
      {"far_vertices",
       [](nlohmann::json& g, std::string&) {
         g["nodes"][0]["scale"] = {1e6, 1e6, 1e6};
         g["nodes"][0]["translation"] = {9e5, 0, 0};
       },
       "1e6"},
      {"metallic_nan_like",
       [](nlohmann::json& g, std::string&) { g["materials"][0]["pbrMetallicRoughness"]["metallicFactor"] = 7; },
       "metallic"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    nlohmann::json gltf = original;
    std::string bytes = bin;
    c.edit(gltf, bytes);
    const fs::path file = dir / (std::string(c.name) + ".gltf");
    gltf["buffers"][0]["uri"] = std::string(c.name) + ".bin";
    test::write_text(dir / (std::string(c.name) + ".bin"), bytes);
    test::write_json(file, gltf);
    const std::string message = input_error_of([&] { load_gltf_mesh(file); });
    ASSERT_FALSE(message.empty()) << "accepted";
    expect_contains(message, file.filename().string());
    expect_contains(message, c.expected);
  }
}

}  // namespace
}  // namespace splat::raytrace
