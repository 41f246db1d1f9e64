// The near bounds of the training cameras: the depth a view's structure-from-motion points
// begin at (a low quantile, so a stray point does not set it), and the test for a position in
// front of it inside some view's frame.
#include "splat/train/points_near_bounds.hpp"

#include <gtest/gtest.h>

namespace splat {
namespace {

// A 100×100 camera at the origin looking down +z.
Camera camera_at_origin() {
  Camera c;
  c.fx = c.fy = 100;
  c.cx = c.cy = 50;
  c.width = c.height = 100;
  return c;
}

// 200 points on the plane z = 10 inside the frame, one stray point at z = 1, and 50 points
// at z = 0.5 outside the frame (x = 5: far to the side).
Dataset dataset_with_points() {
  Dataset d;
  d.train.push_back({"a", camera_at_origin(), Image{}});
  PointCloud points;
  for (int i = 0; i < 200; ++i) {
    const float x = -4.0f + 8.0f * float(i % 20) / 20.0f, y = -4.0f + 8.0f * float(i / 20) / 10.0f;
    points.positions.insert(points.positions.end(), {x, y, 10.0f});
  }
  points.positions.insert(points.positions.end(), {0.0f, 0.0f, 1.0f});
  for (int i = 0; i < 50; ++i) points.positions.insert(points.positions.end(), {5.0f, 0.0f, 0.5f});
  points.colors.assign(points.positions.size(), 0.5f);
  d.points = points;
  return d;
}

TEST(PointsNearBounds, AViewsBoundIsWhereMostOfItsPointsBegin) {
  const std::vector<CameraNearBound> bounds = points_near_bounds(dataset_with_points());
  ASSERT_EQ(bounds.size(), 1u);
  // 201 points in the frame: the 1 % quantile (index 2 of the sorted depths) is on the plane,
  // past the stray point; the points outside the frame do not count.
  EXPECT_FLOAT_EQ(bounds[0].near_depth, 10.0f);
}

TEST(PointsNearBounds, NoPointCloudOrTooFewPointsGiveNoBound) {
  Dataset d = dataset_with_points();
  d.points->positions.resize(3 * std::size_t(kMinPointsForNearBound - 1));
  d.points->colors.resize(d.points->positions.size());
  EXPECT_TRUE(points_near_bounds(d).empty());
  d.points.reset();
  EXPECT_TRUE(points_near_bounds(d).empty());
}

TEST(PointsNearBounds, OnlyPositionsInsideAFrameAndNearerThanTheFactorAreInFront) {
  const std::vector<CameraNearBound> bounds = points_near_bounds(dataset_with_points());
  EXPECT_TRUE(in_front_of_points(bounds, {0, 0, 4}, 0.5f));
  EXPECT_FALSE(in_front_of_points(bounds, {0, 0, 6}, 0.5f));   // past half the bound
  EXPECT_TRUE(in_front_of_points(bounds, {0, 0, 6}, 0.7f));
  EXPECT_FALSE(in_front_of_points(bounds, {4, 0, 4}, 0.5f));   // outside the frame (u = 150)
  EXPECT_FALSE(in_front_of_points(bounds, {0, 0, -4}, 0.5f));  // behind the camera
}

}  // namespace
}  // namespace splat
