#pragma once
// Starting points placed through the training views, for data without a point cloud whose
// content is not confined to a known cube: points spread through the cameras' view frusta,
// and a shell of points far out that can draw the background (sky, distant walls) which
// the images show everywhere. Each point takes its colour from the images that see it.
#include <cstddef>
#include <random>
#include <span>

#include <glm/glm.hpp>

#include "splat/data/dataset.hpp"

namespace splat {

// `count` points, each through a view drawn uniformly from `views`, a position uniform over
// its image, at a distance from the camera centre uniform in disparity (1 / distance)
// between `near` and `far`: so every depth range gets the share of points a perspective
// image gives it (as many between near and 2·near as between 2·near and infinity), and
// far content is reached without emptying the middle. A point's colour is that of the
// pixel it was drawn through.
//
// With `depth_candidates` k > 1, k distances are drawn for the ray and the one the other
// views agree with most is kept: on a surface, the views that see a point show it in one
// colour, while a point in empty space shows each view whatever lies behind it. A vote per
// candidate (the other views that see it, each weighted by how close its pixel's colour is
// to the ray's) is a plane sweep with random depths; it needs no depth maps and costs k ×
// views projections per point. Ties keep the earlier draw, so a ray that no other view sees
// keeps its first distance. k = 1 is plain random depth.
//
// Deterministic for the generator's state (k distances are drawn per point whatever the
// votes). ArgumentError for no views, k < 1, or unless 0 < near < far (finite).
PointCloud frustum_points(std::span<const DatasetView> views, std::size_t count, float near, float far,
                          int depth_candidates, std::mt19937& rng);

// Points spread evenly over the sphere of `radius` around `centre` (a Fibonacci lattice),
// keeping only those some view sees: about `count` of them (the lattice is sized by the
// share of the sphere the views cover), possibly none when no view sees the sphere. A
// point's colour is the mean of the pixels it falls on in the views that see it.
// ArgumentError for no views, count 0 or a radius that is not positive and finite.
PointCloud background_shell(std::span<const DatasetView> views, const glm::vec3& centre, float radius,
                            std::size_t count);

}  // namespace splat
