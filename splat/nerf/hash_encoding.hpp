#pragma once
// Instant-NGP's multiresolution hash encoding (Müller et al. 2022, section 3), forward beside
// its VJPs.
//
// L levels of grids over the unit cube, level l with R_l = ⌊R_min · b^l⌋ cells per axis,
// b = exp((ln R_max − ln R_min)/(L − 1)), so the levels run from R_min to R_max cells. Each
// level has a table of F features per grid vertex: a coarse level whose (R_l + 1)³ vertices
// fit in the table's T = 2^table_log2 entries indexes them densely (x + (R+1)(y + (R+1)z)),
// a finer one hashes them into T entries, h(x, y, z) = (x·1 ⊕ y·2654435761 ⊕ z·805459861)
// mod T (the paper's eq. 4), and lets colliding vertices share the entry: training resolves
// the collisions by where the gradients are largest.
//
// A point u in [0, 1]³ (clamped to it) encodes to F features per level: the trilinear
// interpolation of the 8 vertices of the cell holding u·R_l,
//   out_l = Σ_c w_c(u) · table_l[index(c)],   w_c = Π_a (c_a ? f_a : 1 − f_a),  f = u·R_l − ⌊u·R_l⌋,
// laid out level after level: one sample's code is [L·F] contiguous (column-major [L·F, N]
// for a batch, the MLP's first operand).
//
// The tables live level after level in one array of parameters (entries × F floats per level,
// entry-major). Templated on the scalar so the gradient tests run the same code in double.
#include <cstddef>
#include <string>
#include <vector>

#include "splat/core/setting_value.hpp"

namespace splat {

// Limits (docs/DESIGN.md §4.5): 32 levels of 8 features in 2^24 entries would be 32 GB.
constexpr int kMaxHashLevels = 32;
constexpr int kMaxHashFeatures = 8;
constexpr int kMinHashTableLog2 = 4;
constexpr int kMaxHashTableLog2 = 22;
constexpr int kMaxHashResolution = 1 << 16;
// At most this many table floats (256 MB), whatever the settings above allow one by one.
constexpr std::size_t kMaxHashParameters = std::size_t(1) << 26;

struct HashEncodingSettings {
  int levels = 16;
  int features = 2;        // per level
  int table_log2 = 18;     // entries per level at most 2^table_log2
  int base_resolution = 16;    // R_min, cells per axis of the coarsest level
  int max_resolution = 1024;   // R_max, of the finest

  bool operator==(const HashEncodingSettings&) const = default;
};

template <class Table>
void describe_settings(Table& t, HashEncodingSettings& s) {
  t.number("levels", s.levels, {1, kMaxHashLevels});
  t.number("features", s.features, {1, kMaxHashFeatures});
  t.number("table_log2", s.table_log2, {kMinHashTableLog2, kMaxHashTableLog2});
  t.number("base_resolution", s.base_resolution, {1, kMaxHashResolution});
  t.number("max_resolution", s.max_resolution, {1, kMaxHashResolution});
}

// Throws ArgumentError naming a setting out of range ("path.key"), a max_resolution below
// the base one, or tables of more than kMaxHashParameters floats.
void validate(const HashEncodingSettings& settings, const std::string& path = "");

// Where each level's table sits in the parameters, and its grid.
class HashGridLayout {
 public:
  struct Level {
    int resolution;       // R_l cells per axis, R_l + 1 vertices
    bool dense;           // vertices indexed directly (they fit), else hashed
    std::size_t entries;  // (R_l + 1)³ when dense, else T
    std::size_t offset;   // of the level's first float in the table array
  };

  explicit HashGridLayout(const HashEncodingSettings& settings);

  const HashEncodingSettings& settings() const { return settings_; }
  const std::vector<Level>& levels() const { return levels_; }
  int features() const { return settings_.features; }
  int output_size() const { return settings_.levels * settings_.features; }  // L·F per sample
  std::size_t parameter_count() const { return parameter_count_; }

 private:
  HashEncodingSettings settings_;
  std::vector<Level> levels_;
  std::size_t parameter_count_ = 0;
};

// out [count, L·F] = the codes of unit_positions [count, 3].
template <typename Scalar>
void hash_encode(const HashGridLayout& layout, const Scalar* table, const Scalar* unit_positions, std::size_t count,
                 Scalar* out);

// v_table += ∂L/∂table for one level, from v_out [count, L·F]: each sample's cotangent spread
// over its cell's 8 entries with the interpolation weights, samples in order (the sum's order
// is fixed; the levels write disjoint ranges, so they may run in parallel).
template <typename Scalar>
void hash_encode_vjp_table(const HashGridLayout& layout, int level, const Scalar* unit_positions, std::size_t count,
                           const Scalar* v_out, Scalar* v_table);

// v_unit_positions [count, 3] += ∂L/∂u from v_out [count, L·F] (zero along an axis where u was
// clamped: the encoding is constant there). Per level, ∂w_c/∂u_a = R_l·(c_a ? 1 : −1)·Π_{b≠a}(…).
template <typename Scalar>
void hash_encode_vjp_positions(const HashGridLayout& layout, const Scalar* table, const Scalar* unit_positions,
                               std::size_t count, const Scalar* v_out, Scalar* v_unit_positions);

}  // namespace splat
