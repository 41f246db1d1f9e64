#pragma once
// Initial Gaussians, as the official trainer creates them (create_from_pcd).
#include <cstddef>

#include "splat/data/dataset.hpp"
#include "splat/gaussians/gaussian_model.hpp"

namespace splat {

constexpr float kInitialOpacity = 0.1f;
// Floor on the mean squared neighbour distance, so coincident points get a tiny but finite
// scale instead of log(0).
constexpr float kMinNeighbourDistanceSquared = 1e-7f;
constexpr int kInitNeighbours = 3;
// Blender / NeRF-synthetic scenes have no points: the official trainer scatters this many in
// the cube [−1.3, 1.3]³, which holds the synthetic objects.
constexpr std::size_t kRandomInitCount = 100000;
constexpr float kRandomInitHalfExtent = 1.3f;

// One Gaussian per point, at SH degree `sh_degree`:
//   SH band 0 = (colour − 0.5) / C0 (so the rendered colour is the point's), other bands 0;
//   log_scale = log(sqrt(max(d̄², 1e-7))) on all three axes, where d̄² is the mean squared
//     distance to the 3 nearest other points (exact, nearest_neighbors.hpp);
//   quaternion (1, 0, 0, 0); opacity logit = logit(0.1).
// Throws ArgumentError for an empty cloud, colours that do not match the positions, or a
// degree outside 0..3.
GaussianModel initialize_from_points(const PointCloud& points, int sh_degree);

// The official Blender initialisation: `count` positions uniform in [−half_extent,
// half_extent)³ and SH band 0 uniform in [0, 1/255) per channel, then as from a point cloud.
// Deterministic for a seed (splat/core/random.hpp, positions drawn first, then colours).
//
// The official trainer passes these colours through an 8-bit PLY before using them, which
// truncates every one to 127/255 (band 0 ≈ −0.00695); here the SH values are used as drawn,
// as the code evidently intends. The difference is below one 8-bit colour level.
GaussianModel initialize_random(std::size_t count, float half_extent, unsigned seed,
                                int sh_degree);

// At most `count` of the points, spread evenly through their order (point i·n/count), so a
// Gaussian budget also bounds the starting model. The cloud itself when it is small enough.
PointCloud evenly_subsampled(const PointCloud& points, std::size_t count);

}  // namespace splat
