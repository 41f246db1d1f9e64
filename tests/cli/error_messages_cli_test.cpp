// Bad input to any tool ends the same way: exit status 2 and one line on stderr,
// "error: FILE: what is wrong", with no library's own output before it (libpng's lines,
// nlohmann's "[json.exception...]" ids, a usage text) and no message that names nothing.
// One table over every tool, so a new reader or option is checked the same way.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "tests/cli_support.hpp"
#include "tests/data/png_bytes.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;
using test::CommandResult;

struct BadCall {
  std::string tool;  // the executable
  std::string args;  // with {D} standing for the scratch folder
  std::vector<std::string> expected;  // each must appear in the message
};

std::string expand(std::string text, const fs::path& dir) {
  for (std::size_t at = text.find("{D}"); at != std::string::npos; at = text.find("{D}"))
    text.replace(at, 3, dir.string());
  return text;
}

void write_bad_inputs(const fs::path& dir) {
  test::write_text(dir / "garbage.json", "Mary had a little lamb");
  test::write_text(dir / "garbage.ply", "Mary had a little lamb");
  test::write_text(dir / "garbage.nerf", "Mary had a little lamb");
  test::write_text(dir / "empty.ply", "");
  test::write_text(dir / "empty.json", "{}");
  test::write_text(dir / "a_file", "not a folder");
  fs::create_directories(dir / "a_folder");
  fs::create_directories(dir / "dataset");
  test::write_text(dir / "w.f32", std::string(3 * 8 * 8 * sizeof(float), '\0'));
  // A PNG whose pixel data stops half-way, and one 8x8 image to compare a 32x32 one with.
  std::string rows;
  for (int y = 0; y < 8; ++y) rows += '\0' + std::string(24, '\x40');
  const std::string png = test::png_file(8, 8, 8, 2, rows);
  test::write_text(dir / "cut.png", png.substr(0, png.size() - 20));
  test::write_text(dir / "small.png", png);
  test::write_text(dir / "no_iend.png", png.substr(0, png.size() - 12));  // all pixels, no IEND chunk
  test::write_text(dir / "obj_scene.json", R"({"gltf": "model.obj"})");
  test::write_text(dir / "near_far.json", R"({"random_init_near": 20, "random_init_far": 10})");
}

TEST(ErrorMessages, EveryToolGivesOneLineNamingTheFileAndTheProblem) {
  const fs::path dir = test::scratch_dir("error_messages");
  write_bad_inputs(dir);
  const std::string conformance = test::conformance_dir().string();
  const std::string model = conformance + "/lego_subset50k.ply";
  const std::string cameras = conformance + "/transforms_test.json";
  const std::string jpeg = (fs::path(SPLAT_TEST_DATA_DIR) / "images" / "small.jpg").string();
  const std::vector<BadCall> calls = {
      // splat-psnr
      {SPLAT_PSNR_EXE, "", {"expected two images"}},
      {SPLAT_PSNR_EXE, "{D}/small.png", {"expected two images"}},
      {SPLAT_PSNR_EXE, "{D}/missing.png {D}/small.png", {"{D}/missing.png: does not exist"}},
      {SPLAT_PSNR_EXE, "{D}/cut.png {D}/small.png", {"{D}/cut.png: ", "truncated"}},
      {SPLAT_PSNR_EXE, "{D}/no_iend.png {D}/small.png", {"{D}/no_iend.png: cannot read the PNG"}},
      {SPLAT_PSNR_EXE, "{D}/small.png " + jpeg, {jpeg + ": is 32x32x3 but {D}/small.png is 8x8x3"}},
      {SPLAT_PSNR_EXE, "{D}/a_folder {D}/small.png", {"{D}/small.png: is not a folder"}},
      {SPLAT_PSNR_EXE, "{D}/a_folder {D}/a_folder", {"{D}/a_folder: no PNG images"}},
      // splat-render
      {SPLAT_RENDER_EXE, "--model {D}/a_folder --cameras " + cameras + " --out {D}/o", {"{D}/a_folder: is a folder"}},
      {SPLAT_RENDER_EXE, "--model {D}/empty.ply --cameras " + cameras + " --out {D}/o", {"{D}/empty.ply: not a PLY file"}},
      {SPLAT_RENDER_EXE, "--model {D}/garbage.nerf --cameras " + cameras + " --out {D}/o", {"{D}/garbage.nerf: "}},
      {SPLAT_RENDER_EXE, "--model " + model + " --cameras {D}/garbage.json --out {D}/o", {"{D}/garbage.json: malformed JSON: parse error at line 1"}},
      {SPLAT_RENDER_EXE, "--model " + model + " --cameras {D}/a_folder --out {D}/o", {"{D}/a_folder: is a folder"}},
      {SPLAT_RENDER_EXE, "--model " + model + " --cameras {D}/empty.json --out {D}/o", {"{D}/empty.json: ", "frames"}},
      {SPLAT_RENDER_EXE, "--model " + model + " --cameras " + cameras + " --out {D}/a_file", {"{D}/a_file: cannot create the output folder"}},
      // splat-grad
      {SPLAT_GRAD_EXE, "--model " + model + " --cameras {D}/garbage.json --view 0 --width 8 --height 8 --bg 1,1,1 --weights {D}/w.f32 --out {D}/g.f32", {"{D}/garbage.json: malformed JSON"}},
      // splat-train
      {SPLAT_TRAIN_EXE, "--data {D}/a_file --out {D}/t", {"{D}/a_file: is not a folder"}},
      {SPLAT_TRAIN_EXE, "--data {D}/dataset --out {D}/t", {"{D}/dataset: not a dataset folder"}},
      {SPLAT_TRAIN_EXE, "--data {D}/dataset --out {D}/t --config {D}/a_folder", {"{D}/a_folder: is a folder, not a config file"}},
      {SPLAT_TRAIN_EXE, "--data {D}/dataset --out {D}/t --config {D}/garbage.json", {"{D}/garbage.json: malformed JSON: parse error at line 1"}},
      {SPLAT_TRAIN_EXE, "--data {D}/dataset --out {D}/t --config {D}/missing.json", {"{D}/missing.json: file does not exist"}},
      {SPLAT_TRAIN_EXE, "--data {D}/dataset --out {D}/t --config {D}/near_far.json", {"{D}/near_far.json: \"random_init_near\" must be below"}},
      // splat-scene
      {SPLAT_SCENE_EXE, "", {"expected \"render SCENE.json --out DIR\""}},
      {SPLAT_SCENE_EXE, "render {D}/a_folder --out {D}/s", {"{D}/a_folder: is a folder, not a scene spec"}},
      {SPLAT_SCENE_EXE, "render {D}/garbage.json --out {D}/s", {"{D}/garbage.json: malformed JSON: parse error at line 1"}},
      {SPLAT_SCENE_EXE, "render {D}/empty.json --out {D}/s", {"{D}/empty.json: ", "gltf"}},
      {SPLAT_SCENE_EXE, "render {D}/obj_scene.json --out {D}/s", {"{D}/obj_scene.json: ", "must name a .gltf or .glb file"}},
      // splat-eval
      {SPLAT_EVAL_EXE, "--data {D}/dataset --out {D}/e", {"{D}/dataset: not a dataset folder"}},
      {SPLAT_EVAL_EXE, "--data {D}/dataset --out {D}/e --splat-config {D}/garbage.json", {"{D}/garbage.json: malformed JSON"}},
      // splat-viewer (no window is opened for bad input)
      {SPLAT_VIEWER_EXE, "{D}/garbage.ply {D}/garbage.ply {D}/garbage.ply", {"expected one or two model files, got 3"}},
      {SPLAT_VIEWER_EXE, "{D}/garbage.ply", {"{D}/garbage.ply: not a PLY file"}},
      {SPLAT_VIEWER_EXE, "{D}/garbage.nerf", {"{D}/garbage.nerf: "}},
  };
  for (const BadCall& call : calls) {
    const std::string command = call.tool + " " + expand(call.args, dir);
    const CommandResult r = test::run_command(command, dir);
    EXPECT_EQ(r.exit_code, 2) << command << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << command << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << command << "\n" << r.err;
    EXPECT_EQ(r.err.find("[json.exception"), std::string::npos) << command << "\n" << r.err;
    for (const std::string& expected : call.expected)
      EXPECT_NE(r.err.find(expand(expected, dir)), std::string::npos)
          << command << "\nexpected: " << expand(expected, dir) << "\ngot: " << r.err;
  }
}

}  // namespace
}  // namespace splat
