// Orbit rigs and the transforms writer: what we write reads back as the same cameras.
#include <gtest/gtest.h>

#include "splat/data/orbit_cameras.hpp"
#include "splat/data/transforms_json.hpp"
#include "splat/gaussians/demo_model.hpp"
#include "splat/raster/rasterizer.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

TEST(OrbitCameras, LookAtPutsTheTargetOnTheOpticalAxis) {
  const Camera cam = look_at({3, -2, 1}, {0.5f, 0.2f, -0.3f}, {0, 0, 1}, 300, 300, 200, 100);
  const glm::vec3 target = cam.camera_from_world({0.5f, 0.2f, -0.3f});
  EXPECT_NEAR(target.x, 0, 1e-5);
  EXPECT_NEAR(target.y, 0, 1e-5);
  EXPECT_GT(target.z, 0);
  // World up (+z) appears upward in the image, i.e. towards negative camera y.
  const glm::vec3 above = cam.camera_from_world({0.5f, 0.2f, 0.7f});
  EXPECT_LT(above.y, 0);
  EXPECT_NEAR(glm::determinant(cam.camera_from_world_rotation), 1.0f, 1e-5);
}

TEST(OrbitCameras, WrittenTransformsLoadBackAsTheSameCameras) {
  const auto dir = test::scratch_dir("orbit_roundtrip");
  OrbitRig rig;
  rig.count = 5;
  rig.width = 120;
  rig.height = 80;
  const std::vector<Camera> cams = orbit_cameras(rig);
  std::vector<std::string> names;
  for (int i = 0; i < rig.count; ++i) {
    std::string name = "./views/v";  // built in two steps: GCC 12 warns falsely (-Wrestrict) on "lit" + string
    name += std::to_string(i);
    names.push_back(name);
  }
  write_transforms(dir / "t.json", cams, names);
  const auto frames = load_transforms(dir / "t.json");
  ASSERT_EQ(frames.size(), cams.size());
  for (std::size_t i = 0; i < cams.size(); ++i) {
    const Camera& a = cams[i];
    const Camera& b = frames[i].camera;
    EXPECT_EQ(frames[i].name, names[i].substr(names[i].rfind('/') + 1));
    EXPECT_EQ(b.width, 120);
    EXPECT_EQ(b.height, 80);
    EXPECT_NEAR(a.fx, b.fx, 1e-3);
    EXPECT_NEAR(a.cx, b.cx, 1e-4);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(a.camera_from_world_translation[c], b.camera_from_world_translation[c], 1e-5);
      for (int r = 0; r < 3; ++r)
        EXPECT_NEAR(a.camera_from_world_rotation[c][r], b.camera_from_world_rotation[c][r], 1e-6);
    }
  }
}

TEST(OrbitCameras, AFrameWithItsOwnIntrinsicsKeepsThem) {
  // One camera per image (as COLMAP captures have): each frame's intrinsics survive.
  const auto dir = test::scratch_dir("orbit_roundtrip_intrinsics");
  OrbitRig rig;
  rig.count = 3;
  std::vector<Camera> cams = orbit_cameras(rig);
  cams[1].fx = 321.5f;
  cams[1].cy = 190.25f;
  cams[2] = cams[2].resized(200, 150);
  write_transforms(dir / "t.json", cams, {"a", "b", "c"});
  const auto frames = load_transforms(dir / "t.json");
  ASSERT_EQ(frames.size(), 3u);
  for (std::size_t i = 0; i < cams.size(); ++i) {
    EXPECT_EQ(frames[i].camera.width, cams[i].width) << i;
    EXPECT_EQ(frames[i].camera.height, cams[i].height) << i;
    EXPECT_NEAR(frames[i].camera.fx, cams[i].fx, 1e-3) << i;
    EXPECT_NEAR(frames[i].camera.fy, cams[i].fy, 1e-3) << i;
    EXPECT_NEAR(frames[i].camera.cx, cams[i].cx, 1e-4) << i;
    EXPECT_NEAR(frames[i].camera.cy, cams[i].cy, 1e-4) << i;
  }
}

TEST(DemoModel, IsValidAndVisibleFromItsOrbit) {
  const GaussianModel model = make_demo_model(3000);
  model.check_consistent();
  EXPECT_EQ(model.size(), 3000u);
  OrbitRig rig;
  rig.count = 3;
  rig.radius = 5.5f;
  rig.width = rig.height = 64;
  Rasterizer rasterizer;
  RenderResult result;
  for (const Camera& cam : orbit_cameras(rig)) {
    rasterizer.render(model, cam, RenderSettings{}, result);
    int covered = 0;
    for (float a : result.alpha) covered += a > 0.5f;
    EXPECT_GT(covered, 64 * 64 / 10);   // the sphere fills a good part of the view
    EXPECT_LT(covered, 64 * 64 * 9 / 10);  // and does not fill all of it
  }
}

}  // namespace
}  // namespace splat
