// Fly-through paths and their framing: orbits keep their centre and distance, spirals swing in
// height, interpolation passes through the given views, and framing ignores a few floaters.
#include <gtest/gtest.h>

#include <vector>

#include "splat/core/camera_rig.hpp"
#include "splat/core/error.hpp"
#include "splat/data/camera_paths.hpp"
#include "splat/data/orbit_cameras.hpp"
#include "splat/data/path_framing.hpp"

namespace splat {
namespace {

PathFraming tilted_framing() {
  PathFraming f;
  f.center = {0.5f, -1.0f, 2.0f};
  f.up = glm::normalize(glm::vec3(0.2f, 1.0f, 0.1f));  // not world z: a COLMAP-like capture
  f.start = glm::normalize(glm::cross(f.up, glm::vec3(0, 0, 1)));
  f.distance = 3.0f;
  f.elevation = 0.3f;
  f.fov_y = 0.8f;
  return f;
}

float elevation_of(const Camera& c, const PathFraming& f) {
  const glm::vec3 offset = c.center_in_world() - f.center;
  return std::asin(glm::dot(offset, f.up) / glm::length(offset));
}

TEST(CameraPaths, OrbitLooksAtTheCentreFromItsDistanceUprightAndLoops) {
  const PathFraming f = tilted_framing();
  const std::vector<Camera> cams = orbit_path(f, 12, 64, 48);
  ASSERT_EQ(cams.size(), 12u);
  for (const Camera& c : cams) {
    const glm::vec3 centre = c.camera_from_world(f.center);
    EXPECT_NEAR(centre.x, 0.0f, 1e-4f);
    EXPECT_NEAR(centre.y, 0.0f, 1e-4f);
    EXPECT_NEAR(centre.z, f.distance, 1e-4f);
    EXPECT_NEAR(elevation_of(c, f), f.elevation, 1e-4f);
    // Up points up in the image (camera −y) and the horizon is level (no roll).
    const glm::vec3 up_in_camera = c.camera_from_world_rotation * f.up;
    EXPECT_LT(up_in_camera.y, 0.0f);
    EXPECT_NEAR(up_in_camera.x, 0.0f, 1e-5f);
    EXPECT_EQ(c.width, 64);
    EXPECT_EQ(c.height, 48);
    EXPECT_NEAR(2.0f * std::atan(c.tan_half_fov_y()), f.fov_y, 1e-5f);
    EXPECT_FLOAT_EQ(c.fx, c.fy);
  }
  // Frame 0 is on the start side; neighbours are a twelfth of a turn apart, the last one
  // included (the loop closes).
  const glm::vec3 first = cams[0].center_in_world() - f.center;
  EXPECT_GT(glm::dot(first, f.start), 0.9f * f.distance * std::cos(f.elevation));
  for (std::size_t i = 0; i < cams.size(); ++i) {
    const glm::vec3 a = cams[i].center_in_world(), b = cams[(i + 1) % cams.size()].center_in_world();
    const float chord = 2.0f * f.distance * std::cos(f.elevation) * std::sin(3.14159265f / 12.0f);
    EXPECT_NEAR(glm::length(b - a), chord, 1e-3f) << i;
  }
}

TEST(CameraPaths, SpiralSwingsAboveAndBelowAtTheSameDistance) {
  const PathFraming f = tilted_framing();
  const std::vector<Camera> cams = spiral_path(f, 40, 32, 32);
  float lowest = 10, highest = -10;
  for (const Camera& c : cams) {
    EXPECT_NEAR(glm::length(c.center_in_world() - f.center), f.distance, 1e-4f);
    const glm::vec3 centre = c.camera_from_world(f.center);
    EXPECT_NEAR(centre.x, 0.0f, 1e-4f);
    EXPECT_NEAR(centre.y, 0.0f, 1e-4f);
    lowest = std::min(lowest, elevation_of(c, f));
    highest = std::max(highest, elevation_of(c, f));
  }
  EXPECT_NEAR(elevation_of(cams[0], f), f.elevation, 1e-4f);
  EXPECT_NEAR(highest, f.elevation + kSpiralElevationSwing, 1e-3f);
  EXPECT_NEAR(lowest, f.elevation - kSpiralElevationSwing, 1e-3f);
  EXPECT_LT(lowest, 0.0f);  // below the centre
}

TEST(CameraPaths, ElevationStaysClearOfThePole) {
  PathFraming f = tilted_framing();
  f.elevation = 1.5f;  // nearly straight above: the spiral would pass over the pole
  for (const Camera& c : spiral_path(f, 8, 16, 16)) {
    EXPECT_LE(elevation_of(c, f), kMaxPathElevation + 1e-4f);
    for (int col = 0; col < 3; ++col)
      for (int row = 0; row < 3; ++row) EXPECT_TRUE(std::isfinite(c.camera_from_world_rotation[col][row]));
  }
}

std::vector<Camera> three_views() {
  return {look_at({4, 0, 1}, {0, 0, 0}, {0, 0, 1}, 100, 100, 80, 60),
          look_at({0, 3, 2}, {0, 0, 0.5f}, {0, 0, 1}, 120, 120, 80, 60),
          look_at({-2, -2, 0.5f}, {0.2f, 0, 0}, {0, 0, 1}, 90, 90, 80, 60)};
}

TEST(CameraPaths, InterpolationPassesThroughTheViewsAtTheirFrames) {
  const std::vector<Camera> views = three_views();
  const std::vector<Camera> path = interpolated_path(views, 9, 80, 60);  // views on frames 0, 4, 8
  ASSERT_EQ(path.size(), 9u);
  for (int k = 0; k < 3; ++k) {
    const Camera& p = path[std::size_t(4 * k)];
    const Camera& v = views[std::size_t(k)];
    EXPECT_EQ(p.camera_from_world_rotation, v.camera_from_world_rotation) << k;
    EXPECT_EQ(p.camera_from_world_translation, v.camera_from_world_translation) << k;
    EXPECT_EQ(p.fx, v.fx) << k;
  }
  // Between views: rotations stay rotations, intrinsics lie between their neighbours', and
  // each step moves the camera only part of the way (no jumps).
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    EXPECT_NEAR(glm::determinant(path[i].camera_from_world_rotation), 1.0f, 1e-4f);
    EXPECT_LT(glm::length(path[i + 1].center_in_world() - path[i].center_in_world()), 2.5f) << i;
  }
  EXPECT_GT(path[2].fx, 100.0f);
  EXPECT_LT(path[2].fx, 120.0f);
  // Halfway between the first two views the camera looks halfway between them.
  const glm::vec3 a = optical_axis(views[0]), b = optical_axis(views[1]), mid = optical_axis(path[2]);
  EXPECT_NEAR(glm::dot(mid, a), glm::dot(mid, b), 0.05f);
}

TEST(CameraPaths, InterpolationResizesAndHandlesOneFrameOrOneView) {
  const std::vector<Camera> views = three_views();
  const std::vector<Camera> half = interpolated_path(views, 3, 40, 30);
  EXPECT_EQ(half[1].width, 40);
  EXPECT_FLOAT_EQ(half[1].fx, 60.0f);  // view 1's 120 px focal at half the size
  const std::vector<Camera> one = interpolated_path(views, 1, 80, 60);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].camera_from_world_translation, views[0].camera_from_world_translation);
  const std::vector<Camera> same = interpolated_path(std::span(views).first(1), 4, 80, 60);
  for (const Camera& c : same) EXPECT_EQ(c.camera_from_world_translation, views[0].camera_from_world_translation);
  EXPECT_THROW(interpolated_path({}, 4, 80, 60), ArgumentError);
  EXPECT_THROW(orbit_path(PathFraming{}, 0, 80, 60), ArgumentError);
}

TEST(CameraPaths, RobustBoxIgnoresAFewFarFloatersAndFaintOnes) {
  std::vector<float> xyz, weights;
  for (int i = 0; i <= 200; ++i) {  // a rod from -1 to 1 along x, opaque
    xyz.insert(xyz.end(), {-1.0f + 0.01f * float(i), 0.0f, 0.5f});
    weights.push_back(1.0f);
  }
  for (int i = 0; i < 3; ++i) {  // three opaque floaters far away
    xyz.insert(xyz.end(), {500.0f, -300.0f, 100.0f * float(i)});
    weights.push_back(1.0f);
  }
  for (int i = 0; i < 100; ++i) {  // many nearly transparent ones
    xyz.insert(xyz.end(), {-50.0f, 40.0f, -20.0f});
    weights.push_back(1e-4f);
  }
  const auto box = robust_box(xyz, weights);
  ASSERT_TRUE(box);
  EXPECT_NEAR(box->lo.x, -1.0f, 0.05f);
  EXPECT_NEAR(box->hi.x, 1.0f, 0.05f);
  EXPECT_NEAR(box->lo.y, 0.0f, 1e-6f);
  EXPECT_NEAR(box->hi.z, 0.5f, 1e-6f);
  // Without the weights the faint crowd counts: the box reaches out to it.
  const auto unweighted = robust_box(xyz, {});
  EXPECT_LT(unweighted->lo.x, -40.0f);
  EXPECT_FALSE(robust_box(xyz, std::vector<float>(weights.size(), 0.0f)));
}

TEST(CameraPaths, FramingABoxFitsItsBallInTheNarrowerSide) {
  const AxisAlignedBox box{{-1, -2, 0}, {1, 2, 1}};
  const PathFraming f = frame_box(box, {0, 0, 1}, 2.0f);
  EXPECT_EQ(f.center, glm::vec3(0, 0, 0.5f));
  EXPECT_NEAR(std::abs(glm::dot(f.start, f.up)), 0.0f, 1e-6f);
  // Every corner of the box projects inside every orbit image.
  for (const float aspect : {2.0f, 0.5f}) {
    const PathFraming g = frame_box(box, {0, 0, 1}, aspect);
    const int width = aspect > 1 ? 128 : 32, height = aspect > 1 ? 64 : 64;
    for (const Camera& c : orbit_path(g, 16, width, height))
      for (int corner = 0; corner < 8; ++corner) {
        const glm::vec3 p((corner & 1) ? box.hi.x : box.lo.x, (corner & 2) ? box.hi.y : box.lo.y,
                          (corner & 4) ? box.hi.z : box.lo.z);
        EXPECT_TRUE(in_view(c, p)) << aspect << " corner " << corner;
      }
  }
}

TEST(CameraPaths, FramingFromCamerasFollowsTheCapture) {
  // A capture with y up (not world z), cameras 5 away from (1, 2, 3), 0.4 rad above it.
  const glm::vec3 focus(1, 2, 3), up(0, 1, 0);
  std::vector<Camera> capture;
  for (int i = 0; i < 6; ++i) {
    const float azimuth = 0.7f + 0.5f * float(i);
    const glm::vec3 eye = focus + 5.0f * glm::vec3(std::cos(0.4f) * std::cos(azimuth), std::sin(0.4f),
                                                   std::cos(0.4f) * std::sin(azimuth));
    capture.push_back(look_at(eye, focus, up, 100, 100, 100, 80));
  }
  const PathFraming f = frame_from_cameras(capture, AxisAlignedBox{{-9, -9, -9}, {-8, -8, -8}});
  EXPECT_LT(glm::length(f.center - focus), 1e-3f);
  EXPECT_NEAR(glm::dot(f.up, up), 1.0f, 1e-4f);
  EXPECT_NEAR(f.distance, 5.0f, 1e-3f);
  EXPECT_NEAR(f.elevation, 0.4f, 1e-3f);
  EXPECT_NEAR(f.fov_y, 2.0f * std::atan(0.4f), 1e-5f);
  // The orbit's first camera stands where the first capture camera does.
  const Camera first = orbit_path(f, 8, 100, 80).front();
  EXPECT_LT(glm::length(first.center_in_world() - capture[0].center_in_world()), 1e-3f);
  // Cameras that do not converge (all looking the same way) fall back to the content's centre.
  const std::vector<Camera> parallel = {look_at({0, 0, 0}, {0, 0, -1}, up, 100, 100, 100, 80),
                                        look_at({1, 0, 0}, {1, 0, -1}, up, 100, 100, 100, 80)};
  const PathFraming g = frame_from_cameras(parallel, AxisAlignedBox{{-1, -1, -6}, {1, 1, -4}});
  EXPECT_LT(glm::length(g.center - glm::vec3(0, 0, -5)), 1e-5f);
}

TEST(CameraPaths, CaptureUpIsLevelEvenWhenTheCamerasStandOnOneSide) {
  // Five cameras 50 degrees up, all on one side of the object (a quarter turn): their mean up
  // leans over to the other side, but their right vectors are all level.
  const glm::vec3 up = glm::normalize(glm::vec3(0.1f, -1.0f, 0.2f));  // a COLMAP-like "down is +y"
  const glm::vec3 side = glm::normalize(glm::cross(up, glm::vec3(1, 0, 0))), across = glm::cross(up, side);
  std::vector<Camera> capture;
  glm::vec3 mean_up(0.0f);
  for (int i = 0; i < 5; ++i) {
    const float azimuth = 0.4f * float(i);
    const glm::vec3 eye = 3.0f * (std::cos(0.87f) * (std::cos(azimuth) * side + std::sin(azimuth) * across) +
                                  std::sin(0.87f) * up);
    capture.push_back(look_at(eye, glm::vec3(0.0f), up, 100, 100, 64, 64));
    const glm::mat3& r = capture.back().camera_from_world_rotation;
    mean_up -= glm::vec3(r[0][1], r[1][1], r[2][1]);
  }
  EXPECT_LT(glm::dot(glm::normalize(mean_up), up), 0.95f);  // the naive estimate is 18+ degrees off
  EXPECT_GT(glm::dot(capture_up(capture, glm::vec3(0.0f), {0, 0, 1}), up), 0.99999f);
  // The same photographs stored turned by 90 degrees (as phones do): every right vector is
  // vertical now, and the ring the cameras stand on says where up is.
  std::vector<Camera> turned;
  const glm::mat3 quarter_turn(glm::vec3(0, -1, 0), glm::vec3(1, 0, 0), glm::vec3(0, 0, 1));  // x' = y, y' = −x
  for (Camera c : capture) {
    c.camera_from_world_rotation = quarter_turn * c.camera_from_world_rotation;
    c.camera_from_world_translation = quarter_turn * c.camera_from_world_translation;
    turned.push_back(c);
  }
  EXPECT_LT(glm::length(turned[2].center_in_world() - capture[2].center_in_world()), 1e-5f);
  EXPECT_GT(glm::dot(capture_up(turned, glm::vec3(0.0f), {0, 0, 1}), up), 0.9999f);
  // Cameras all facing one way leave their right vectors no spread: the mean up decides.
  const std::vector<Camera> forward = {look_at({0, 0, 0}, {0, 0, -1}, up, 100, 100, 64, 64),
                                       look_at({1, 0, 0}, {1, 0, -1}, up, 100, 100, 64, 64)};
  EXPECT_GT(glm::dot(capture_up(forward, std::nullopt, {0, 0, 1}), glm::normalize(up - glm::dot(up, glm::vec3(0, 0, 1)) * glm::vec3(0, 0, 1))),
            0.9999f);
}

}  // namespace
}  // namespace splat
