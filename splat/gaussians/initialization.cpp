#include "splat/gaussians/initialization.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "splat/core/error.hpp"
#include "splat/core/random.hpp"
#include "splat/core/spherical_harmonics.hpp"
#include "splat/gaussians/nearest_neighbors.hpp"

namespace splat {
namespace {

// Upper bound (exclusive) of the random SH band-0 values: a colour within one 8-bit level of
// mid-grey.
constexpr float kRandomShDcRange = 1.0f / 255.0f;

// Fills a model of the cloud's size with everything but band 0 of the SH.
GaussianModel gaussians_at(const std::vector<float>& positions, int sh_degree) {
  GaussianModel model;
  model.sh_degree = sh_degree;
  const std::size_t n = positions.size() / 3;
  model.resize(n);  // zero-filled: higher SH bands start at 0
  model.means = positions;

  const std::vector<float> distance2 =
      mean_squared_neighbour_distance(positions, kInitNeighbours);
  // In float, as the official trainer computes it on the GPU.
  const float opacity_logit = logit(kInitialOpacity);
  for (std::size_t i = 0; i < n; ++i) {
    const float log_scale =
        std::log(std::sqrt(std::max(distance2[i], kMinNeighbourDistanceSquared)));
    for (int a = 0; a < 3; ++a) model.log_scales[3 * i + a] = log_scale;
    model.quats[4 * i] = 1.0f;
    model.opacity_logits[i] = opacity_logit;
  }
  return model;
}

void check_degree(int sh_degree, const char* who) {
  if (sh_degree < 0 || sh_degree > kMaxShDegree)
    throw ArgumentError(std::string(who) + ": SH degree " + std::to_string(sh_degree) +
                        " is outside 0.." + std::to_string(kMaxShDegree));
}

}  // namespace

GaussianModel initialize_from_points(const PointCloud& points, int sh_degree) {
  check_degree(sh_degree, "initialize_from_points");
  if (points.size() == 0)
    throw ArgumentError("initialize_from_points: the point cloud is empty");
  if (points.positions.size() % 3 != 0 || points.colors.size() != points.positions.size())
    throw ArgumentError("initialize_from_points: " + std::to_string(points.positions.size()) +
                        " position and " + std::to_string(points.colors.size()) +
                        " colour values do not form matching [P, 3] arrays");

  GaussianModel model = gaussians_at(points.positions, sh_degree);
  const std::size_t row = std::size_t(model.sh_coefficients()) * 3;
  const float c0 = float(kShC0);
  for (std::size_t i = 0; i < model.size(); ++i)
    for (int c = 0; c < 3; ++c)
      model.sh[i * row + c] = (points.colors[3 * i + c] - 0.5f) / c0;
  return model;
}

GaussianModel initialize_random(std::size_t count, float half_extent, unsigned seed,
                                int sh_degree) {
  check_degree(sh_degree, "initialize_random");
  if (count == 0) throw ArgumentError("initialize_random: zero Gaussians requested");
  if (!(half_extent > 0.0f))
    throw ArgumentError("initialize_random: half extent " + std::to_string(half_extent) +
                        " is not positive");

  std::mt19937 rng(seed);
  std::vector<float> positions(count * 3);
  for (float& x : positions) x = (2.0f * uniform01(rng) - 1.0f) * half_extent;

  GaussianModel model = gaussians_at(positions, sh_degree);
  const std::size_t row = std::size_t(model.sh_coefficients()) * 3;
  for (std::size_t i = 0; i < count; ++i)
    for (int c = 0; c < 3; ++c) model.sh[i * row + c] = uniform01(rng) * kRandomShDcRange;
  return model;
}

PointCloud evenly_subsampled(const PointCloud& points, std::size_t count) {
  const std::size_t n = points.size();
  if (count >= n) return points;
  PointCloud kept;
  kept.positions.reserve(3 * count);
  kept.colors.reserve(3 * count);
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t source = i * n / count;
    for (int k = 0; k < 3; ++k) {
      kept.positions.push_back(points.positions[3 * source + k]);
      kept.colors.push_back(points.colors[3 * source + k]);
    }
  }
  return kept;
}

}  // namespace splat
