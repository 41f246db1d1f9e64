#pragma once
// A coarse occupancy grid over the scene box, to skip samples in empty space (after
// Instant-NGP, Müller et al. 2022, section 4 "Accelerated ray marching").
//
// Each cell keeps a running density value; it is occupied while that value is above a
// threshold. The update rule (Instant-NGP's):
//   every cell:        value ← decay · value
//   evaluated cells:   value ← max(value, σ(a point in the cell))
//   every cell:        occupied ← value > min(threshold, mean of all values)
// so a cell that stops showing density empties after a few updates (0.95ⁿ), while any one
// high sample reopens it at once. Before the first update every cell is occupied (the field
// is untrained; nothing may be skipped yet). Nothing here depends on the thread count: the
// points are drawn from the caller's RNG in a fixed order and the per-cell steps are
// element-wise.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <random>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "splat/core/rays.hpp"
#include "splat/nerf/scene_space.hpp"

namespace splat {

// The largest grid side: 256³ cells hold 84 MB (a float and a flag each); 1,024 would be 5 GB.
constexpr int kMaxOccupancyResolution = 256;

struct OccupancyUpdateOptions {
  float decay = 0.95f;    // multiplies every cell's value before the new samples
  bool jitter = true;     // a uniform random point in each evaluated cell, else its centre
  std::size_t cells = 0;  // cells evaluated: 0 (or ≥ the cell count) = all, in index order;
                          // otherwise this many, drawn uniformly (with replacement) from the RNG
};

class OccupancyGrid {
 public:
  // σ at each point: sigmas[i] = density(points[i]). Called from the updating thread with
  // batches of up to kBatch points; it may parallelise internally.
  using DensityFunction =
      std::function<void(std::span<const glm::vec3> points, std::span<float> sigmas)>;
  static constexpr std::size_t kBatch = 1 << 16;

  // resolution³ cells over `box`, a cell occupied while its value > `threshold` (a density
  // σ: with σ ≤ 0.01 a sample of length δ has α ≤ 0.01·δ). Throws ArgumentError for a
  // resolution outside [1, 1024] or an empty box.
  explicit OccupancyGrid(const AxisAlignedBox& box, int resolution = 64, float threshold = 0.01f);

  // Whether the cell holding p is occupied; false outside the box (nothing is there).
  bool occupied(const glm::vec3& p) const {
    const std::ptrdiff_t cell = cell_index(p);
    return cell >= 0 && occupied_[std::size_t(cell)] != 0;
  }

  // One update of the rule above. Not thread-safe (it reuses internal scratch buffers).
  void update(const DensityFunction& density, std::mt19937& rng,
              const OccupancyUpdateOptions& options = {});

  int resolution() const { return resolution_; }
  const AxisAlignedBox& box() const { return box_; }
  float threshold() const { return threshold_; }
  std::size_t cell_count() const { return occupied_.size(); }
  std::size_t occupied_count() const;
  // Cell (x, y, z), x fastest: index x + r·(y + r·z).
  std::size_t cell(int x, int y, int z) const {
    const std::size_t r = std::size_t(resolution_);
    return std::size_t(x) + r * (std::size_t(y) + r * std::size_t(z));
  }
  bool cell_occupied(std::size_t cell) const { return occupied_[cell] != 0; }
  float cell_value(std::size_t cell) const { return value_[cell]; }
  glm::vec3 cell_center(std::size_t cell) const;

  // The whole state (values and flags, which differ before the first update), for model
  // files and checkpoints; restore throws ArgumentError unless both have cell_count() entries.
  std::span<const float> values() const { return value_; }
  std::span<const std::uint8_t> occupancy() const { return occupied_; }
  void restore(std::span<const float> values, std::span<const std::uint8_t> occupied);

 private:
  // The cell holding p, or −1 outside the box (the upper faces belong to the last cells).
  std::ptrdiff_t cell_index(const glm::vec3& p) const;

  AxisAlignedBox box_;
  int resolution_;
  float threshold_;
  glm::vec3 cells_per_unit_;            // resolution / box size, per axis
  glm::vec3 cell_size_;                 // box size / resolution
  std::vector<float> value_;            // [r³] decayed running max of σ
  std::vector<std::uint8_t> occupied_;  // [r³] 1 = may hold density
  // Scratch reused across updates.
  std::vector<std::uint32_t> batch_cells_;  // [≤ kBatch]
  std::vector<glm::vec3> batch_points_;     // [≤ kBatch]
  std::vector<float> batch_sigmas_;         // [≤ kBatch]
};

// Keeps, in order, the samples of `ray` whose point origin + t·direction lies in an occupied
// cell (the grid spans `space`'s network coordinates): they are moved to the front of t and
// delta, each with its own δ (the dropped ones leave gaps, not longer intervals). Returns how
// many were kept.
std::size_t drop_empty_samples(const OccupancyGrid& grid, const SceneSpace& space, const Ray& ray,
                               std::span<float> t, std::span<float> delta);

}  // namespace splat
