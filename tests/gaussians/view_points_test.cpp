// Points placed through the training views: in the frusta, and on a background shell.
#include "splat/gaussians/view_points.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "splat/core/camera_rig.hpp"
#include "splat/core/error.hpp"
#include "splat/data/orbit_cameras.hpp"

namespace splat {
namespace {

// Views on an orbit of radius 4 round the origin, each image one flat colour of its own.
std::vector<DatasetView> orbit_views(int count) {
  OrbitRig rig;
  rig.count = count;
  rig.radius = 4.0f;
  rig.elevation_radians = 0.3f;
  rig.fov_x_radians = 1.0f;
  rig.width = 40;
  rig.height = 30;
  std::vector<DatasetView> views;
  for (const Camera& camera : orbit_cameras(rig)) {
    DatasetView view;
    view.camera = camera;
    const float shade = float(views.size()) / float(count);
    view.image = Image(camera.width, camera.height, 3);
    for (int y = 0; y < camera.height; ++y)
      for (int x = 0; x < camera.width; ++x) {
        view.image.at(x, y, 0) = shade;
        view.image.at(x, y, 1) = 0.25f;
        view.image.at(x, y, 2) = 0.75f;
      }
    views.push_back(view);
  }
  return views;
}

glm::vec3 at(const std::vector<float>& xyz, std::size_t i) { return {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]}; }

TEST(FrustumPoints, EveryPointIsInAViewBetweenNearAndFar) {
  const std::vector<DatasetView> views = orbit_views(6);
  std::mt19937 rng(3);
  const PointCloud cloud = frustum_points(views, 3000, 1.0f, 20.0f, 1, rng);
  ASSERT_EQ(cloud.size(), 3000u);
  double mean_disparity = 0;
  std::size_t beyond_four = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const glm::vec3 p = at(cloud.positions, i);
    // Some view has it in its image, at a distance in [near, far] (and the colour is that
    // view's, so the one it came through: the shade names the view).
    bool found = false;
    for (const DatasetView& view : views) {
      const float distance = glm::length(p - view.camera.center_in_world());
      if (in_view(view.camera, p) && distance >= 1.0f - 1e-3f && distance <= 20.0f + 1e-2f &&
          std::abs(view.image.at(0, 0, 0) - cloud.colors[3 * i]) < 1e-6f) {
        found = true;
        mean_disparity += 1.0 / distance;
        beyond_four += distance > 4.0f;
      }
    }
    ASSERT_TRUE(found) << "point " << i;
    EXPECT_FLOAT_EQ(cloud.colors[3 * i + 1], 0.25f);
  }
  // Uniform in disparity on [1/20, 1]: mean 0.525, and P(distance > 4) = (1/4 − 1/20) / (1 − 1/20).
  EXPECT_NEAR(mean_disparity / 3000.0, 0.525, 0.02);
  EXPECT_NEAR(double(beyond_four) / 3000.0, 0.2 / 0.95, 0.03);
}

TEST(FrustumPoints, DeterministicForASeedAndCheckedArguments) {
  const std::vector<DatasetView> views = orbit_views(4);
  std::mt19937 a(7), b(7), c(8);
  const PointCloud pa = frustum_points(views, 200, 0.5f, 9.0f, 4, a);
  EXPECT_EQ(pa.positions, frustum_points(views, 200, 0.5f, 9.0f, 4, b).positions);
  EXPECT_NE(pa.positions, frustum_points(views, 200, 0.5f, 9.0f, 4, c).positions);
  std::mt19937 rng(1);
  EXPECT_THROW(frustum_points({}, 10, 1.0f, 2.0f, 1, rng), ArgumentError);
  EXPECT_THROW(frustum_points(views, 10, 0.0f, 2.0f, 1, rng), ArgumentError);
  EXPECT_THROW(frustum_points(views, 10, 2.0f, 2.0f, 1, rng), ArgumentError);
  EXPECT_THROW(frustum_points(views, 10, 1.0f, INFINITY, 1, rng), ArgumentError);
  EXPECT_THROW(frustum_points(views, 10, 1.0f, 2.0f, 0, rng), ArgumentError);
}

// Views from above onto a floor (the plane z = 0) painted with smooth waves of colour, each
// image showing exactly the floor: where a pixel's ray meets it, the paint there.
std::vector<DatasetView> views_of_a_painted_floor() {
  OrbitRig rig;
  rig.count = 12;
  rig.radius = 6.0f;
  rig.elevation_radians = 0.9f;
  rig.fov_x_radians = 0.8f;
  rig.width = rig.height = 48;
  std::vector<DatasetView> views;
  for (const Camera& camera : orbit_cameras(rig)) {
    DatasetView view;
    view.camera = camera;
    view.image = Image(48, 48, 3, 0.0f);
    const glm::mat3 to_world = glm::transpose(camera.camera_from_world_rotation);
    const glm::vec3 origin = camera.center_in_world();
    for (int y = 0; y < 48; ++y)
      for (int x = 0; x < 48; ++x) {
        const glm::vec3 d = to_world * glm::vec3((x + 0.5f - camera.cx) / camera.fx, (y + 0.5f - camera.cy) / camera.fy, 1);
        if (!(d.z < 0)) continue;
        const glm::vec3 hit = origin - d * (origin.z / d.z);
        view.image.at(x, y, 0) = 0.5f + 0.5f * std::sin(3.0f * hit.x);
        view.image.at(x, y, 1) = 0.5f + 0.5f * std::sin(2.3f * hit.y);
        view.image.at(x, y, 2) = 0.5f + 0.5f * std::sin(1.7f * (hit.x + hit.y));
      }
    views.push_back(view);
  }
  return views;
}

TEST(FrustumPoints, DepthCandidatesFindTheSurfaceTheViewsAgreeOn) {
  const std::vector<DatasetView> views = views_of_a_painted_floor();
  const auto near_the_floor = [&](int candidates) {
    std::mt19937 rng(11);
    const PointCloud cloud = frustum_points(views, 1500, 2.0f, 40.0f, candidates, rng);
    std::size_t near = 0;
    for (std::size_t i = 0; i < cloud.size(); ++i) near += std::abs(cloud.positions[3 * i + 2]) < 0.3f;
    return double(near) / double(cloud.size());
  };
  const double plain = near_the_floor(1), voted = near_the_floor(16);
  // Within 0.3 of the floor is about 1/20 of the disparity range: random depths put about
  // that share there (0.045). Sixteen draws hold a depth that close about half the time,
  // and the vote picks it in nearly all of those (0.47).
  EXPECT_LT(plain, 0.1);
  EXPECT_GT(voted, 0.4);
}

TEST(BackgroundShell, PointsOnTheSphereThatTheViewsSeeAboutTheCountAsked) {
  const std::vector<DatasetView> views = orbit_views(8);
  const glm::vec3 centre(0.0f, 0.0f, 0.0f);
  const PointCloud shell = background_shell(views, centre, 40.0f, 2000);
  EXPECT_NEAR(double(shell.size()), 2000.0, 100.0);
  float lowest = 1.0f, highest = -1.0f;
  for (std::size_t i = 0; i < shell.size(); ++i) {
    const glm::vec3 p = at(shell.positions, i);
    EXPECT_NEAR(glm::length(p - centre), 40.0f, 1e-3f);
    int seen = 0;
    float shade = 0;
    for (const DatasetView& view : views)
      if (in_view(view.camera, p)) ++seen, shade += view.image.at(0, 0, 0);
    ASSERT_GT(seen, 0);
    EXPECT_NEAR(shell.colors[3 * i], shade / float(seen), 1e-5f);  // the mean of the views seeing it
    EXPECT_FLOAT_EQ(shell.colors[3 * i + 2], 0.75f);
    lowest = std::min(lowest, p.z / 40.0f);
    highest = std::max(highest, p.z / 40.0f);
  }
  // The cameras, 1.2 above the centre, look 0.3 rad down with a vertical half field of view
  // of about 0.39 rad: the shell is the band they see (from about 0.09 rad above the
  // horizon to 0.69 below, give or take their height), not the whole sphere.
  EXPECT_LT(highest, std::sin(0.15f));
  EXPECT_GT(highest, std::sin(0.05f));
  EXPECT_GT(lowest, -std::sin(0.75f));
  EXPECT_LT(lowest, -std::sin(0.6f));
}

TEST(BackgroundShell, DeterministicAndEmptyWhenNoViewSeesIt) {
  const std::vector<DatasetView> views = orbit_views(5);
  EXPECT_EQ(background_shell(views, {}, 30.0f, 500).positions, background_shell(views, {}, 30.0f, 500).positions);
  // A small sphere far above the cameras, which all look down at the origin.
  EXPECT_EQ(background_shell(views, {0, 0, 100}, 1.0f, 500).size(), 0u);
  EXPECT_THROW(background_shell(views, {}, 0.0f, 500), ArgumentError);
  EXPECT_THROW(background_shell(views, {}, 30.0f, 0), ArgumentError);
  EXPECT_THROW(background_shell({}, {}, 30.0f, 500), ArgumentError);
}

}  // namespace
}  // namespace splat
