// splat-scene render: a bad spec exits 2 with "error:" and writes nothing; a good tiny spec
// exits 0 and writes the whole dataset.
#include <gtest/gtest.h>

#include "tests/cli_support.hpp"
#include "tests/raytrace/scene_test_files.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

TEST(SceneCli, BadSpecExitsTwoAndWritesNothing) {
  const fs::path dir = test::scratch_dir("scene_cli_bad");
  test::write_test_gltf(dir / "plane.gltf", test::plane_mesh(2, 0));
  nlohmann::json spec = test::tiny_spec("plane.gltf");
  spec["cameras"]["radius"] = -2;
  test::write_json(dir / "scene.json", spec);
  const auto r = test::run_command(std::string(SPLAT_SCENE_EXE) + " render " +
                                       (dir / "scene.json").string() + " --out " + (dir / "out").string(),
                                   dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("scene.json"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("cameras.radius"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(SceneCli, GoodSpecWritesTheDataset) {
  const fs::path dir = test::scratch_dir("scene_cli_good");
  test::write_test_gltf(dir / "plane.gltf", test::plane_mesh(2, 0));
  test::write_json(dir / "scene.json", test::tiny_spec("plane.gltf"));
  const auto r = test::run_command(std::string(SPLAT_SCENE_EXE) + " render " +
                                       (dir / "scene.json").string() + " --out " + (dir / "out").string(),
                                   dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("rendered 5/5 views"), std::string::npos) << r.out;
  for (const char* file : {"transforms_train.json", "transforms_test.json", "train/r_0.png",
                           "train/r_2.png", "test/r_1.png", "depth/train/r_2.exr", "depth/test/r_0.exr"})
    EXPECT_TRUE(fs::exists(dir / "out" / file)) << file;
  // Nothing left under a temporary name.
  for (const auto& entry : fs::recursive_directory_iterator(dir / "out"))
    EXPECT_EQ(entry.path().filename().string().find("tmp"), std::string::npos) << entry.path();
}

}  // namespace
}  // namespace splat
