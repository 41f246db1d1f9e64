#include "splat/gaussians/gaussian_model.hpp"

#include <algorithm>
#include <string>

#include "splat/core/error.hpp"

namespace splat {
namespace {

// Calls f(array_of_a, array_of_b, floats_per_row) for every parameter group of two models
// with the same layout, so each row operation is written once for all arrays.
template <class ModelA, class ModelB, class F>
void for_each_array_pair(ModelA& a, ModelB& b, F&& f) {
  for (const ParameterGroup& group : kParameterGroups) f(group.of(a), group.of(b), group.width(a.sh_degree));
}

template <class Model, class F>
void for_each_array(Model& m, F&& f) {
  for_each_array_pair(m, m, [&](auto& array, auto&, std::size_t width) { f(array, width); });
}

void require_same_degree(const GaussianModel& a, const GaussianModel& b, const char* what) {
  if (a.sh_degree != b.sh_degree)
    throw ArgumentError(std::string("GaussianModel::") + what + ": SH degree " +
                        std::to_string(b.sh_degree) + " does not match " +
                        std::to_string(a.sh_degree));
}

}  // namespace

void GaussianModel::resize(std::size_t n) {
  for_each_array(*this, [n](std::vector<float>& array, std::size_t width) { array.resize(n * width); });
}

std::size_t GaussianModel::floats_per_row() const {
  std::size_t floats = 0;
  for (const ParameterGroup& group : kParameterGroups) floats += group.width(sh_degree);
  return floats;
}

void GaussianModel::check_consistent() const {
  if (sh_degree < 0 || sh_degree > kMaxShDegree)
    throw ArgumentError("GaussianModel: SH degree " + std::to_string(sh_degree) +
                        " is outside 0.." + std::to_string(kMaxShDegree));
  const std::size_t n = size();
  for (const ParameterGroup& group : kParameterGroups)
    if (group.of(*this).size() != n * group.width(sh_degree))
      throw ArgumentError("GaussianModel: parameter arrays disagree in length for " + std::to_string(n) +
                          " Gaussians");
}

void GaussianModel::keep_rows(const std::vector<std::uint8_t>& keep) {
  const std::size_t n = size();
  if (keep.size() != n)
    throw ArgumentError("GaussianModel::keep_rows: " + std::to_string(keep.size()) +
                        " flags for " + std::to_string(n) + " rows");
  // Compaction in place: a kept row only ever moves towards the front, so it never
  // overwrites a row that is still to be read.
  for_each_array(*this, [&](std::vector<float>& array, std::size_t width) {
    std::size_t out = 0;
    for (std::size_t row = 0; row < n; ++row) {
      if (!keep[row]) continue;
      if (out != row)
        std::copy_n(array.begin() + row * width, width, array.begin() + out * width);
      ++out;
    }
    array.resize(out * width);
  });
}

void GaussianModel::append_rows(const GaussianModel& other) {
  require_same_degree(*this, other, "append_rows");
  for_each_array_pair(*this, other,
                      [](std::vector<float>& mine, const std::vector<float>& theirs,
                         std::size_t) { mine.insert(mine.end(), theirs.begin(), theirs.end()); });
}

void GaussianModel::append_zero_rows(std::size_t count) { resize(size() + count); }

GaussianModel GaussianModel::gather_rows(const std::vector<std::size_t>& rows) const {
  const std::size_t n = size();
  for (std::size_t row : rows)
    if (row >= n)
      throw ArgumentError("GaussianModel::gather_rows: row " + std::to_string(row) +
                          " of " + std::to_string(n));
  GaussianModel out;
  out.sh_degree = sh_degree;
  out.resize(rows.size());
  for_each_array_pair(out, *this,
                      [&](std::vector<float>& dst, const std::vector<float>& src,
                          std::size_t width) {
                        for (std::size_t i = 0; i < rows.size(); ++i)
                          std::copy_n(src.begin() + rows[i] * width, width,
                                      dst.begin() + i * width);
                      });
  return out;
}

void GaussianModel::copy_row(std::size_t row, const GaussianModel& source,
                             std::size_t source_row) {
  require_same_degree(*this, source, "copy_row");
  if (row >= size() || source_row >= source.size())
    throw ArgumentError("GaussianModel::copy_row: row out of range");
  for_each_array_pair(*this, source,
                      [&](std::vector<float>& dst, const std::vector<float>& src,
                          std::size_t width) {
                        std::copy_n(src.begin() + source_row * width, width,
                                    dst.begin() + row * width);
                      });
}

void GaussianModel::zero_row(std::size_t row) {
  if (row >= size()) throw ArgumentError("GaussianModel::zero_row: row out of range");
  for_each_array(*this, [&](std::vector<float>& array, std::size_t width) {
    std::fill_n(array.begin() + row * width, width, 0.0f);
  });
}

void GaussianModel::set_zero() {
  for_each_array(*this, [](std::vector<float>& array, std::size_t) {
    std::fill(array.begin(), array.end(), 0.0f);
  });
}

void GaussianModel::add(const GaussianModel& other) {
  require_same_degree(*this, other, "add");
  if (other.size() != size())
    throw ArgumentError("GaussianModel::add: " + std::to_string(other.size()) + " rows added to " +
                        std::to_string(size()));
  for_each_array_pair(*this, other, [](std::vector<float>& a, const std::vector<float>& b, std::size_t) {
    for (std::size_t i = 0; i < a.size(); ++i) a[i] += b[i];
  });
}

void GaussianModel::write_values(std::span<float> out) const {
  if (out.size() != value_count())
    throw ArgumentError("GaussianModel::write_values: " + std::to_string(out.size()) + " slots for " +
                        std::to_string(value_count()) + " values");
  std::size_t at = 0;
  for_each_array(*this, [&](const std::vector<float>& array, std::size_t) {
    std::copy(array.begin(), array.end(), out.begin() + std::ptrdiff_t(at));
    at += array.size();
  });
}

void GaussianModel::read_values(std::span<const float> in) {
  if (in.size() != value_count())
    throw ArgumentError("GaussianModel::read_values: " + std::to_string(in.size()) + " values for " +
                        std::to_string(value_count()) + " slots");
  std::size_t at = 0;
  for_each_array(*this, [&](std::vector<float>& array, std::size_t) {
    std::copy(in.begin() + std::ptrdiff_t(at), in.begin() + std::ptrdiff_t(at + array.size()), array.begin());
    at += array.size();
  });
}

void GaussianModel::multiply(float factor) {
  for_each_array(*this, [factor](std::vector<float>& array, std::size_t) {
    for (float& v : array) v *= factor;
  });
}

}  // namespace splat
