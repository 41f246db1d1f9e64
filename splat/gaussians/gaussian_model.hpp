#pragma once
// The Gaussian model as a structure of arrays. Parameters are stored raw, exactly as the
// standard 3DGS PLY stores them; activations are applied on use (docs/DESIGN.md §3.2), through
// the accessors below:
//   scale = exp(log_scale), opacity = sigmoid(opacity_logit), rotation = normalize(quat),
//   colour = SH(dir) + 0.5 clamped at 0.
// kParameterGroups, after the model, is the one list of its arrays that everything iterating
// "every parameter" goes through.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <span>
#include <vector>

#include "splat/core/activations.hpp"
#include "splat/gaussians/covariance.hpp"

namespace splat {

constexpr int kMaxShDegree = 3;
// The most Gaussians a model file may hold (docs/DESIGN.md §4.1): the official trainer's
// largest scenes have about 6 million; 2^24 at SH degree 3 is 4 GB of parameters.
constexpr std::size_t kMaxGaussiansInAFile = std::size_t(1) << 24;
// Number of SH coefficients per colour channel for a degree: (degree + 1)^2.
constexpr int sh_coefficient_count(int degree) { return (degree + 1) * (degree + 1); }
// The most SH floats one Gaussian holds (degree 3, RGB).
constexpr int kMaxShFloats = 3 * sh_coefficient_count(kMaxShDegree);

struct GaussianModel {
  int sh_degree = 0;                     // 0..3
  std::vector<float> means;              // [N, 3] world position
  std::vector<float> log_scales;         // [N, 3]
  std::vector<float> quats;              // [N, 4] (w, x, y, z), not necessarily unit
  std::vector<float> opacity_logits;     // [N]
  std::vector<float> sh;                 // [N, K, 3], K = sh_coefficient_count(sh_degree);
                                         // coefficient-major, RGB innermost (k = 0 is the DC band)

  std::size_t size() const { return opacity_logits.size(); }
  int sh_coefficients() const { return sh_coefficient_count(sh_degree); }

  // Gaussian i's parameters as they act: its mean, its axes' scales exp(log_scale), its
  // opacity sigmoid(logit), its quaternion as stored (w, x, y, z; not necessarily unit, which
  // gradients need) and the rotation of the normalised quaternion.
  Vec3<float> mean(std::size_t i) const { return {means[3 * i], means[3 * i + 1], means[3 * i + 2]}; }
  Vec3<float> scale(std::size_t i) const {
    return {std::exp(log_scales[3 * i]), std::exp(log_scales[3 * i + 1]), std::exp(log_scales[3 * i + 2])};
  }
  float opacity(std::size_t i) const { return sigmoid(opacity_logits[i]); }
  Vec4<float> quat(std::size_t i) const { return {quats[4 * i], quats[4 * i + 1], quats[4 * i + 2], quats[4 * i + 3]}; }
  Mat3<float> rotation(std::size_t i) const { return quat_to_rotmat(quat(i)); }

  // Resizes every array for n Gaussians at the current SH degree (new entries zero).
  void resize(std::size_t n);
  // Throws ArgumentError if the arrays disagree in length or the degree is out of range.
  void check_consistent() const;

  // Row operations. Gradients and Adam moments share this shape, so density control applies
  // the same operation to parameters and optimiser state and the rows stay aligned.

  // Keeps the rows whose flag is non-zero, in their order. `keep` has one flag per row.
  void keep_rows(const std::vector<std::uint8_t>& keep);
  // Appends the rows of `other` after the existing ones. Throws ArgumentError unless
  // `other` has the same SH degree.
  void append_rows(const GaussianModel& other);
  // Appends `count` rows of zeros (fresh Adam moments for new Gaussians).
  void append_zero_rows(std::size_t count);
  // A new model holding the listed rows in the listed order (repeats allowed), same degree.
  GaussianModel gather_rows(const std::vector<std::size_t>& rows) const;
  // Copies row `source_row` of `source` (same degree) over row `row` of this model.
  void copy_row(std::size_t row, const GaussianModel& source, std::size_t source_row);
  // Every value of row `row` zero (fresh Adam moments for a moved Gaussian).
  void zero_row(std::size_t row);
  // Every value zero, size and degree kept.
  void set_zero();
  // Element-wise this += other, for gradients (same degree and size; ArgumentError otherwise).
  void add(const GaussianModel& other);
  // Every value times `factor`.
  void multiply(float factor);
  // All values as one flat array (means, log-scales, quaternions, opacities, SH), to send a
  // gradient between processes: value_count() floats into `out`; read_values takes them back
  // into a model already sized alike. ArgumentError on a size mismatch.
  std::size_t value_count() const { return size() * floats_per_row(); }
  void write_values(std::span<float> out) const;
  void read_values(std::span<const float> in);
  // Floats per row across all arrays: 3 + 3 + 4 + 1 + 3·K (59 at degree 3).
  std::size_t floats_per_row() const;
};

enum class ParameterGroupId { kMeans, kLogScales, kQuats, kOpacityLogits, kSh };

// One parameter array of the model and its row width.
struct ParameterGroup {
  ParameterGroupId id;
  const char* name;                           // as errors name it ("non-finite quaternions")
  std::vector<float> GaussianModel::*values;  // model.*values is the array
  // Floats per Gaussian: fixed_floats + floats_per_sh_coefficient × K (only SH grows with K).
  int fixed_floats, floats_per_sh_coefficient;

  std::size_t width(int sh_degree) const {
    return std::size_t(fixed_floats + floats_per_sh_coefficient * sh_coefficient_count(sh_degree));
  }
  std::vector<float>& of(GaussianModel& model) const { return model.*values; }
  const std::vector<float>& of(const GaussianModel& model) const { return model.*values; }
};

// The model's parameter groups, in the one order every consumer keeps: the row operations,
// the flat layout of write_values (what ranks exchange), checkpoints, Adam and the divergence
// check iterate this list, so a group added or renamed is added everywhere at once. (The PLY
// file has its own column order, fixed by the format; ply_io.cpp maps its columns onto these
// groups.)
inline constexpr ParameterGroup kParameterGroups[] = {
    {ParameterGroupId::kMeans, "means", &GaussianModel::means, 3, 0},
    {ParameterGroupId::kLogScales, "log_scales", &GaussianModel::log_scales, 3, 0},
    {ParameterGroupId::kQuats, "quaternions", &GaussianModel::quats, 4, 0},
    {ParameterGroupId::kOpacityLogits, "opacity_logits", &GaussianModel::opacity_logits, 1, 0},
    {ParameterGroupId::kSh, "sh_coefficients", &GaussianModel::sh, 0, 3},  // [K, 3] per row
};

static_assert([] {
  for (int i = 0; i < int(std::size(kParameterGroups)); ++i)
    if (int(kParameterGroups[i].id) != i) return false;
  return true;
}(), "kParameterGroups is in ParameterGroupId order");

// The entry of kParameterGroups for `id`.
constexpr const ParameterGroup& parameter_group(ParameterGroupId id) { return kParameterGroups[int(id)]; }

}  // namespace splat
