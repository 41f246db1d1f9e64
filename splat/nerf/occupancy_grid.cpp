#include "splat/nerf/occupancy_grid.hpp"

#include <algorithm>
#include <string>
#include <tbb/parallel_for.h>

#include "splat/core/error.hpp"
#include "splat/core/random.hpp"

namespace splat {

OccupancyGrid::OccupancyGrid(const AxisAlignedBox& box, int resolution, float threshold)
    : box_(box), resolution_(resolution), threshold_(threshold) {
  if (resolution < 1 || resolution > kMaxOccupancyResolution)
    throw ArgumentError("occupancy grid: resolution " + std::to_string(resolution) + " is outside [1, " +
                        std::to_string(kMaxOccupancyResolution) + "]");
  const glm::vec3 size = box.hi - box.lo;
  if (!(size.x > 0 && size.y > 0 && size.z > 0))
    throw ArgumentError("occupancy grid: the box is empty");
  cells_per_unit_ = float(resolution) / size;
  cell_size_ = size / float(resolution);
  const std::size_t count = std::size_t(resolution) * resolution * resolution;
  value_.assign(count, 0.0f);
  occupied_.assign(count, 1);  // all occupied until the first update
}

std::ptrdiff_t OccupancyGrid::cell_index(const glm::vec3& p) const {
  if (!box_.contains(p)) return -1;  // also false for NaN
  int index[3];
  for (int a = 0; a < 3; ++a)
    index[a] = std::min(resolution_ - 1, int((p[a] - box_.lo[a]) * cells_per_unit_[a]));
  return std::ptrdiff_t(cell(index[0], index[1], index[2]));
}

glm::vec3 OccupancyGrid::cell_center(std::size_t c) const {
  const std::size_t r = std::size_t(resolution_);
  const glm::vec3 index(float(c % r), float(c / r % r), float(c / (r * r)));
  return box_.lo + (index + 0.5f) * cell_size_;
}

void OccupancyGrid::restore(std::span<const float> values, std::span<const std::uint8_t> occupied) {
  if (values.size() != cell_count() || occupied.size() != cell_count())
    throw ArgumentError("occupancy grid: restoring " + std::to_string(values.size()) + " values and " +
                        std::to_string(occupied.size()) + " flags into " + std::to_string(cell_count()) +
                        " cells");
  std::copy(values.begin(), values.end(), value_.begin());
  for (std::size_t c = 0; c < occupied.size(); ++c) occupied_[c] = occupied[c] ? 1 : 0;
}

std::size_t OccupancyGrid::occupied_count() const {
  return std::size_t(std::count(occupied_.begin(), occupied_.end(), std::uint8_t(1)));
}

void OccupancyGrid::update(const DensityFunction& density, std::mt19937& rng,
                           const OccupancyUpdateOptions& options) {
  const std::size_t count = cell_count();
  const float decay = options.decay;
  tbb::parallel_for(std::size_t(0), count, [&](std::size_t c) { value_[c] *= decay; });

  const bool all = options.cells == 0 || options.cells >= count;
  const std::size_t evaluations = all ? count : options.cells;
  const std::size_t r = std::size_t(resolution_);
  for (std::size_t start = 0; start < evaluations; start += kBatch) {
    const std::size_t n = std::min(kBatch, evaluations - start);
    batch_cells_.resize(n);
    batch_points_.resize(n);
    batch_sigmas_.resize(n);
    // Serial, in a fixed order: the RNG stream (and so every point) is the same for any
    // thread count.
    for (std::size_t k = 0; k < n; ++k) {
      // A uniform cell: the high 32 bits of draw·count (count ≤ 1024³ < 2³²).
      const std::size_t c =
          all ? start + k : std::size_t((std::uint64_t(rng()) * count) >> 32);
      glm::vec3 offset(0.5f);
      if (options.jitter) {
        offset.x = uniform01(rng);
        offset.y = uniform01(rng);
        offset.z = uniform01(rng);
      }
      const glm::vec3 index(float(c % r), float(c / r % r), float(c / (r * r)));
      batch_cells_[k] = std::uint32_t(c);
      batch_points_[k] = box_.lo + (index + offset) * cell_size_;
    }
    density(std::span<const glm::vec3>(batch_points_), std::span<float>(batch_sigmas_));
    // Max is order-independent, so repeated cells give the same value in any order.
    for (std::size_t k = 0; k < n; ++k)
      value_[batch_cells_[k]] = std::max(value_[batch_cells_[k]], batch_sigmas_[k]);
  }

  // Instant-NGP's rule: the threshold falls to the mean value when the field is faint
  // everywhere (early in training), so the grid then keeps the cells denser than the rest
  // rather than emptying and starving every ray of samples. Summed serially in double: the
  // same mean for any thread count.
  double sum = 0;
  for (const float v : value_) sum += v;
  const float threshold = std::min(threshold_, float(sum / double(count)));
  tbb::parallel_for(std::size_t(0), count,
                    [&](std::size_t c) { occupied_[c] = value_[c] > threshold ? 1 : 0; });
}

std::size_t drop_empty_samples(const OccupancyGrid& grid, const SceneSpace& space, const Ray& ray,
                               std::span<float> t, std::span<float> delta) {
  if (t.size() != delta.size())
    throw ArgumentError("drop_empty_samples: t and delta differ in size (" +
                        std::to_string(t.size()) + " vs " + std::to_string(delta.size()) + ")");
  std::size_t kept = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (!grid.occupied(space.to_network(ray.origin + t[i] * ray.direction))) continue;
    t[kept] = t[i];
    delta[kept] = delta[i];
    ++kept;
  }
  return kept;
}

}  // namespace splat
