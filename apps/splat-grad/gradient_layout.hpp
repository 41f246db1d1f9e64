#pragma once
// The gradient table layout shared with the official implementation: one row per Gaussian,
// columns in PLY property order without the normals.
#include <string>
#include <vector>

#include "splat/gaussians/gaussian_model.hpp"

namespace splat::cli {

// 3 (xyz) + 3 (f_dc) + 3·(K−1) (f_rest) + 1 (opacity) + 3 (scale) + 4 (rot): 59 for degree 3.
int gradient_columns(int sh_degree);

// [N, gradient_columns] with f_rest channel-major as the PLY stores it.
std::vector<float> gradient_table(const GaussianModel& grads);

struct GroupComparison {
  std::string name;          // xyz, f_dc, f_rest, opacity, scale, rotation
  double reference_norm = 0;
  double relative_error = 0;  // ‖g − g_ref‖ / ‖g_ref‖
};
std::vector<GroupComparison> compare_gradient_groups(const std::vector<float>& ours,
                                                     const std::vector<float>& reference,
                                                     int sh_degree);

}  // namespace splat::cli
