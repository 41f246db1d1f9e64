#include "splat/nerf/hash_encoding.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "splat/core/error.hpp"
#include "splat/core/settings_table.hpp"

namespace splat {

void validate(const HashEncodingSettings& s, const std::string& path) {
  check_setting_ranges(s, path);
  if (s.max_resolution < s.base_resolution)
    throw ArgumentError("\"" + (path.empty() ? "" : path + ".") + "max_resolution\" must be at least base_resolution (" +
                        std::to_string(s.base_resolution) + "), got " + std::to_string(s.max_resolution));
  const std::size_t bound = std::size_t(s.levels) * std::size_t(s.features) << s.table_log2;
  if (bound > kMaxHashParameters)
    throw ArgumentError("\"" + (path.empty() ? "" : path + ".") + "table_log2\": " + std::to_string(s.levels) +
                        " levels of " + std::to_string(s.features) + " features in 2^" + std::to_string(s.table_log2) +
                        " entries exceed " + std::to_string(kMaxHashParameters) + " table values");
}

HashGridLayout::HashGridLayout(const HashEncodingSettings& settings) : settings_(settings) {
  validate(settings_);
  const double growth =
      settings_.levels > 1
          ? std::exp((std::log(double(settings_.max_resolution)) - std::log(double(settings_.base_resolution))) /
                     double(settings_.levels - 1))
          : 1.0;
  const std::size_t table = std::size_t(1) << settings_.table_log2;
  for (int l = 0; l < settings_.levels; ++l) {
    Level level{};
    // The last level lands on R_max exactly, whatever exp and log round to.
    level.resolution = l == settings_.levels - 1 && settings_.levels > 1
                           ? settings_.max_resolution
                           : std::max(1, int(std::floor(double(settings_.base_resolution) * std::pow(growth, l))));
    const std::size_t vertices = std::size_t(level.resolution + 1) * std::size_t(level.resolution + 1) *
                                 std::size_t(level.resolution + 1);
    level.dense = vertices <= table;
    level.entries = level.dense ? vertices : table;
    level.offset = parameter_count_;
    parameter_count_ += level.entries * std::size_t(settings_.features);
    levels_.push_back(level);
  }
}

// Samples per block: the corners of a block's samples are found lane-parallel (one pass of
// arithmetic over the block per step, which the compiler vectorises), then their entries are
// gathered, a corner at a time for the whole block. Scalar code per sample spent ~20 cycles
// per table lookup on the arithmetic alone.
namespace {

constexpr int kBlock = 16;

// Corner c of sample j of a block: its entry's first float (index · F) and its weight; and
// the sample's place in its cell along each axis, which the weights are made of.
template <typename Scalar>
struct BlockCorners {
  std::int32_t entry[8][kBlock];
  Scalar weight[8][kBlock];
  Scalar frac[3][kBlock];
};

// The corners on `level` of samples [first, first + n) (n ≤ kBlock).
template <typename Scalar>
void locate_block(const HashGridLayout::Level& level, int features, const Scalar* unit_positions,
                  std::size_t first, int n, BlockCorners<Scalar>& corners) {
  const Scalar resolution = Scalar(level.resolution), last_cell = Scalar(level.resolution - 1);
  std::uint32_t lo[3][kBlock];
  Scalar(&frac)[3][kBlock] = corners.frac;
  for (int a = 0; a < 3; ++a)
    for (int j = 0; j < n; ++j) {
      const Scalar u = unit_positions[3 * (first + std::size_t(j)) + std::size_t(a)];
      // Clamped to [0, 1], NaN to 0 (every comparison with it is false): a cell index from NaN
      // would be undefined behaviour.
      const Scalar s = (u > Scalar(0) ? (u < Scalar(1) ? u : Scalar(1)) : Scalar(0)) * resolution;
      const Scalar floor_s = std::min(std::floor(s), last_cell);  // the upper face: the last cell
      lo[a][j] = std::uint32_t(floor_s);
      frac[a][j] = s - floor_s;
    }
  const std::uint32_t side = std::uint32_t(level.resolution) + 1, mask = std::uint32_t(level.entries - 1);
  const std::uint32_t f_count = std::uint32_t(features);
  for (int c = 0; c < 8; ++c) {
    const std::uint32_t dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
    if (level.dense)
      for (int j = 0; j < n; ++j)
        corners.entry[c][j] =
            std::int32_t(f_count * (lo[0][j] + dx + side * (lo[1][j] + dy + side * (lo[2][j] + dz))));
    else
      // The paper's primes; the first is 1 so that neighbours along x stay neighbours in memory.
      for (int j = 0; j < n; ++j)
        corners.entry[c][j] = std::int32_t(
            f_count * (((lo[0][j] + dx) ^ ((lo[1][j] + dy) * 2654435761u) ^ ((lo[2][j] + dz) * 805459861u)) & mask));
    for (int j = 0; j < n; ++j)
      corners.weight[c][j] = (dx ? frac[0][j] : 1 - frac[0][j]) * (dy ? frac[1][j] : 1 - frac[1][j]) *
                             (dz ? frac[2][j] : 1 - frac[2][j]);
  }
}

}  // namespace

template <typename Scalar>
void hash_encode(const HashGridLayout& layout, const Scalar* table, const Scalar* unit_positions, std::size_t count,
                 Scalar* out) {
  const int f_count = layout.features();
  const std::size_t stride = std::size_t(layout.output_size());
  BlockCorners<Scalar> corners;
  for (std::size_t first = 0; first < count; first += kBlock) {
    const int n = int(std::min<std::size_t>(kBlock, count - first));
    for (std::size_t l = 0; l < layout.levels().size(); ++l) {
      const HashGridLayout::Level& level = layout.levels()[l];
      locate_block(level, f_count, unit_positions, first, n, corners);
      for (int f = 0; f < f_count; ++f) {
        const Scalar* __restrict entries = table + level.offset + std::size_t(f);
        Scalar sum[kBlock] = {};
        for (int c = 0; c < 8; ++c)
          for (int j = 0; j < n; ++j) sum[j] += corners.weight[c][j] * entries[corners.entry[c][j]];
        for (int j = 0; j < n; ++j)
          out[stride * (first + std::size_t(j)) + l * std::size_t(f_count) + std::size_t(f)] = sum[j];
      }
    }
  }
}

template <typename Scalar>
void hash_encode_vjp_table(const HashGridLayout& layout, int level_index, const Scalar* unit_positions,
                           std::size_t count, const Scalar* v_out, Scalar* v_table) {
  const int f_count = layout.features();
  const std::size_t stride = std::size_t(layout.output_size());
  const HashGridLayout::Level& level = layout.levels()[std::size_t(level_index)];
  Scalar* entries = v_table + level.offset;
  BlockCorners<Scalar> corners;
  for (std::size_t first = 0; first < count; first += kBlock) {
    const int n = int(std::min<std::size_t>(kBlock, count - first));
    locate_block(level, f_count, unit_positions, first, n, corners);
    // Scattered in sample order (entries collide, so this part stays serial).
    for (int j = 0; j < n; ++j) {
      const Scalar* v = v_out + stride * (first + std::size_t(j)) + std::size_t(level_index) * std::size_t(f_count);
      bool any = false;
      for (int f = 0; f < f_count; ++f) any |= v[f] != Scalar(0);
      if (!any) continue;  // samples past a ray's end carry no cotangent
      for (int c = 0; c < 8; ++c) {
        Scalar* entry = entries + corners.entry[c][j];
        for (int f = 0; f < f_count; ++f) entry[f] += corners.weight[c][j] * v[f];
      }
    }
  }
}

namespace {

// One sample's cell on one level, with what the position VJP needs.
template <typename Scalar>
struct Cell {
  std::uint32_t index[8];  // entry of corner c = (c&1, c>>1&1, c>>2&1)
  Scalar frac[3];          // f_a, the point's place in the cell
  bool inside[3];          // the point was within [0, 1] on axis a (else clamped)
};

template <typename Scalar>
Cell<Scalar> locate(const HashGridLayout::Level& level, const Scalar* u) {
  BlockCorners<Scalar> corners;
  locate_block(level, 1, u, 0, 1, corners);
  Cell<Scalar> cell;
  for (int c = 0; c < 8; ++c) cell.index[c] = std::uint32_t(corners.entry[c][0]);
  for (int a = 0; a < 3; ++a) {
    cell.inside[a] = u[a] >= Scalar(0) && u[a] <= Scalar(1);  // false for NaN
    cell.frac[a] = corners.frac[a][0];
  }
  return cell;
}

}  // namespace

template <typename Scalar>
void hash_encode_vjp_positions(const HashGridLayout& layout, const Scalar* table, const Scalar* unit_positions,
                               std::size_t count, const Scalar* v_out, Scalar* v_unit_positions) {
  const int f_count = layout.features();
  const std::size_t stride = std::size_t(layout.output_size());
  for (std::size_t i = 0; i < count; ++i) {
    const Scalar* u = unit_positions + 3 * i;
    for (std::size_t l = 0; l < layout.levels().size(); ++l) {
      const HashGridLayout::Level& level = layout.levels()[l];
      const Cell<Scalar> cell = locate(level, u);
      const Scalar* v = v_out + stride * i + l * std::size_t(f_count);
      const Scalar* entries = table + level.offset;
      for (int c = 0; c < 8; ++c) {
        // v · table entry: how much the code moves per unit of this corner's weight.
        const Scalar* entry = entries + std::size_t(cell.index[c]) * std::size_t(f_count);
        Scalar dot = 0;
        for (int f = 0; f < f_count; ++f) dot += v[f] * entry[f];
        for (int a = 0; a < 3; ++a) {
          if (!cell.inside[a]) continue;
          Scalar d = Scalar(level.resolution) * (((c >> a) & 1) ? Scalar(1) : Scalar(-1));
          for (int b = 0; b < 3; ++b)
            if (b != a) d *= ((c >> b) & 1) ? cell.frac[b] : 1 - cell.frac[b];
          v_unit_positions[3 * i + std::size_t(a)] += d * dot;
        }
      }
    }
  }
}

#define SPLAT_INSTANTIATE_HASH_ENCODING(Scalar)                                                                   \
  template void hash_encode<Scalar>(const HashGridLayout&, const Scalar*, const Scalar*, std::size_t, Scalar*); \
  template void hash_encode_vjp_table<Scalar>(const HashGridLayout&, int, const Scalar*, std::size_t,           \
                                              const Scalar*, Scalar*);                                          \
  template void hash_encode_vjp_positions<Scalar>(const HashGridLayout&, const Scalar*, const Scalar*,          \
                                                  std::size_t, const Scalar*, Scalar*);
SPLAT_INSTANTIATE_HASH_ENCODING(float)
SPLAT_INSTANTIATE_HASH_ENCODING(double)
#undef SPLAT_INSTANTIATE_HASH_ENCODING

}  // namespace splat
