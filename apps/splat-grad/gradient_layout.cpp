#include "apps/splat-grad/gradient_layout.hpp"

#include <cmath>

namespace splat::cli {

int gradient_columns(int sh_degree) {
  return 3 + 3 * sh_coefficient_count(sh_degree) + 1 + 3 + 4;
}

std::vector<float> gradient_table(const GaussianModel& grads) {
  const std::size_t n = grads.size();
  const int k_count = grads.sh_coefficients();
  const int columns = gradient_columns(grads.sh_degree);
  std::vector<float> table(n * columns);
  for (std::size_t i = 0; i < n; ++i) {
    float* row = &table[i * columns];
    int col = 0;
    for (int a = 0; a < 3; ++a) row[col++] = grads.means[3 * i + a];
    for (int c = 0; c < 3; ++c) row[col++] = grads.sh[(i * k_count) * 3 + c];
    for (int c = 0; c < 3; ++c)
      for (int k = 1; k < k_count; ++k) row[col++] = grads.sh[(i * k_count + k) * 3 + c];
    row[col++] = grads.opacity_logits[i];
    for (int a = 0; a < 3; ++a) row[col++] = grads.log_scales[3 * i + a];
    for (int a = 0; a < 4; ++a) row[col++] = grads.quats[4 * i + a];
  }
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
