#pragma once
// Exact k-nearest-neighbour distances over a point cloud, for the initial Gaussian scales
// (the official trainer's distCUDA2: the mean squared distance to the 3 nearest other points).
#include <cstdint>
#include <vector>

namespace splat {

constexpr std::uint32_t kNoNeighbour = 0xFFFFFFFFu;

// For every point of `positions` ([P, 3]), the mean of the squared distances to its k nearest
// other points ([P]). Squared distances are computed in float from the coordinates, and the k
// best are summed nearest first, as distCUDA2 does. Duplicated points count as neighbours at
// distance 0. With fewer than k other points the mean is over those there are, and a lone
// point gets 0. If `neighbours` is given it receives their indices ([P, k], nearest first,
// kNoNeighbour where missing; among equal distances, either may appear).
//
// A k-d tree (median splits along the widest axis) searched exactly: a subtree is skipped only
// when no point in it can be strictly closer than the current k-th best. Queries run in
// parallel, each independent, so the result is the same for any thread count.
std::vector<float> mean_squared_neighbour_distance(const std::vector<float>& positions, int k,
                                                   std::vector<std::uint32_t>* neighbours =
                                                       nullptr);

}  // namespace splat
