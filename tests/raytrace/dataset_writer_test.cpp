// A dataset written from a scene spec loads through splat::load_dataset with exactly the
// orbit rig's cameras, and test views differ from training views.
#include <gtest/gtest.h>

#include "splat/raytrace/dataset_writer.hpp"
#include "splat/raytrace/orbit_rig.hpp"
#include "tests/raytrace/scene_test_files.hpp"
#include "splat/data/dataset.hpp"
#include "splat/data/image_io.hpp"
#include "tests/test_support.hpp"

namespace splat::raytrace {
namespace {

namespace fs = std::filesystem;

void expect_same_camera(const Camera& a, const Camera& b) {
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_NEAR(a.fx, b.fx, 1e-5f * a.fx);
  EXPECT_NEAR(a.fy, b.fy, 1e-5f * a.fy);
  EXPECT_NEAR(a.cx, b.cx, 1e-5f);
  EXPECT_NEAR(a.cy, b.cy, 1e-5f);
  for (int col = 0; col < 3; ++col) {
    EXPECT_NEAR(a.camera_from_world_translation[col], b.camera_from_world_translation[col], 1e-5f);
    for (int row = 0; row < 3; ++row)
      EXPECT_NEAR(a.camera_from_world_rotation[col][row], b.camera_from_world_rotation[col][row], 1e-5f);
  }
}

TEST(SceneDataset, LoadsWithTheOrbitRigsCameras) {
  const fs::path dir = test::scratch_dir("scene_dataset");
  test::write_test_gltf(dir / "cube.gltf", test::cube_mesh(0.5f));
  test::write_json(dir / "scene.json", test::tiny_spec("cube.gltf"));
  const SceneSpec spec = load_scene_spec(dir / "scene.json");
  const Mesh mesh = load_gltf_mesh(spec.gltf);
  int last_done = 0, last_total = 0;
  write_scene_dataset(spec, mesh, dir / "out", [&](int done, int total) {
    last_done = done;
    last_total = total;
  });
  EXPECT_EQ(last_done, 5);
  EXPECT_EQ(last_total, 5);

  const Dataset data = load_dataset(dir / "out");
  const std::vector<Camera> train = orbit_rig_cameras(spec.cameras, Split::train);
  const std::vector<Camera> test = orbit_rig_cameras(spec.cameras, Split::test);
  ASSERT_EQ(data.train.size(), train.size());
  ASSERT_EQ(data.test.size(), test.size());
  for (std::size_t i = 0; i < train.size(); ++i) {
    EXPECT_EQ(data.train[i].name, "r_" + std::to_string(i));
    expect_same_camera(train[i], data.train[i].camera);
    // The target sits on the optical axis, in front of the camera at the rig's radius.
    const glm::vec3 target = data.train[i].camera.camera_from_world(spec.cameras.target);
    EXPECT_NEAR(target.x, 0.0f, 1e-5f);
    EXPECT_NEAR(target.y, 0.0f, 1e-5f);
    EXPECT_NEAR(target.z, spec.cameras.radius, 1e-5f);
  }
  for (std::size_t i = 0; i < test.size(); ++i) {
    expect_same_camera(test[i], data.test[i].camera);
    for (const Camera& t : train)
      EXPECT_GT(glm::length(t.center_in_world() - test[i].center_in_world()), 0.1f);
  }
  // RGBA images and one-channel float depth beside them.
  const ImageInfo png = read_image_info(dir / "out/train/r_0.png");
  EXPECT_EQ(png.channels, 4);
  const Image depth = read_image(dir / "out/depth/test/r_1.exr");
  EXPECT_EQ(depth.channels, 1);
  EXPECT_EQ(depth.width, spec.cameras.width);
  float max_depth = 0;
  for (float d : depth.data) max_depth = std::max(max_depth, d);
  EXPECT_GT(max_depth, 3.0f);  // the cube's near faces are about radius − 0.5 .. radius away
  EXPECT_LT(max_depth, 4.5f);
}

}  // namespace
}  // namespace splat::raytrace
