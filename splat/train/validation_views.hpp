#pragma once
// Which training views the validation holdout takes. A held-out view is one the model is
// not fitted to while it grows, so the choice costs the most where a view is the only one
// that sees part of the scene from near its place: a close-up or a view from above whose
// neighbours are far. Holding such a view out leaves a gap the test views next to it fall
// into (issue 40: real_cup's test close-up 61 scored 15–16 dB with its neighbour 60 held
// out, 22 dB without). So the holdout takes the most redundant views instead: those whose
// nearest neighbour is closest, and never two that are near each other, so that every held
// out view keeps close neighbours in training and the views spread over the capture.
#include <cstddef>
#include <vector>

#include "splat/data/dataset.hpp"

namespace splat {

// How far apart two views are: the distance between their centres over the nearer one's
// distance to the scene centre (a close-up 10 cm from its neighbour is as far from it as a
// distant view 1 m away), plus the angle between their viewing directions in radians.
float view_distance(const Camera& a, const Camera& b, const glm::vec3& scene_center);

// Indices into `train` (ascending) of up to ceil(size / every) views: the views in order of
// their nearest neighbour's distance (ties to the lower index), each taken unless it is one
// of the three nearest to a view already taken or has such a view among its own three
// nearest. The scene centre is `scene_centre(train, &points)`: the points' per-axis median
// (the cameras' mean when there are none).
std::vector<std::size_t> choose_validation_views(const std::vector<DatasetView>& train, const PointCloud& points,
                                                 int every);

}  // namespace splat
