#include "apps/splat-grad/gradient_layout.hpp"

#include <cmath>

#include "splat/gaussians/ply_io.hpp"

namespace splat::cli {

namespace {

// The PLY's columns less the normals: the gradient table's, in order.
std::vector<PlyColumn> gradient_layout(int sh_degree) {
  std::vector<PlyColumn> columns = official_ply_columns(sh_degree);
  std::erase_if(columns, [](const PlyColumn& c) { return c.array == nullptr; });
  return columns;
}

}  // namespace

int gradient_columns(int sh_degree) { return int(gradient_layout(sh_degree).size()); }

std::vector<float> gradient_table(const GaussianModel& grads) {
  const std::size_t n = grads.size();
  const std::vector<PlyColumn> layout = gradient_layout(grads.sh_degree);
  std::vector<float> table(n * layout.size());
  float* out = table.data();
  for (std::size_t i = 0; i < n; ++i)
    for (const PlyColumn& c : layout) *out++ = (grads.*c.array)[c.first + i * c.stride];
  return table;
}

std::vector<GroupComparison> compare_gradient_groups(const std::vector<float>& ours,
                                                     const std::vector<float>& reference,
                                                     int sh_degree) {
  const int columns = gradient_columns(sh_degree);
  const int rest = 3 * (sh_coefficient_count(sh_degree) - 1);
  struct Span { const char* name; int first, count; };
  const Span spans[] = {{"xyz", 0, 3},          {"f_dc", 3, 3},          {"f_rest", 6, rest},
                        {"opacity", 6 + rest, 1}, {"scale", 7 + rest, 3}, {"rotation", 10 + rest, 4}};
  std::vector<GroupComparison> out;
  const std::size_t n = ours.size() / columns;
  for (const Span& span : spans) {
    double diff = 0, norm = 0;
    for (std::size_t i = 0; i < n; ++i)
      for (int c = span.first; c < span.first + span.count; ++c) {
        const double a = ours[i * columns + c], b = reference[i * columns + c];
        diff += (a - b) * (a - b);
        norm += b * b;
      }
    out.push_back({span.name, std::sqrt(norm), norm > 0 ? std::sqrt(diff / norm) : std::sqrt(diff)});
  }
  return out;
}

}  // namespace splat::cli
