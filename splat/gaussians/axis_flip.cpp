#include "splat/gaussians/axis_flip.hpp"

#include <cmath>

#include "splat/core/spherical_harmonics.hpp"

namespace splat {
namespace {

// The sign each SH basis function takes under (x, y, z) → (x, −y, −z): its value at a
// direction with no zero component, turned, over its value unturned. Read off the basis
// itself so that the table cannot disagree with the renderer's basis order.
void basis_signs(int degree, float* signs) {
  const double length = std::sqrt(0.3 * 0.3 + 0.5 * 0.5 + 0.8 * 0.8);
  const double x = 0.3 / length, y = 0.5 / length, z = 0.8 / length;
  double plain[sh_coefficient_count(kMaxShDegree)], turned[sh_coefficient_count(kMaxShDegree)];
  sh_basis_xyz(degree, x, y, z, plain);
  sh_basis_xyz(degree, x, -y, -z, turned);
  for (int k = 0; k < sh_coefficient_count(degree); ++k) signs[k] = turned[k] / plain[k] > 0 ? 1.0f : -1.0f;
}

}  // namespace

void turn_half_about_x(GaussianModel& model) {
  float signs[sh_coefficient_count(kMaxShDegree)];
  basis_signs(model.sh_degree, signs);
  const std::size_t coefficients = static_cast<std::size_t>(model.sh_coefficients());
  for (std::size_t i = 0; i < model.size(); ++i) {
    model.means[3 * i + 1] = -model.means[3 * i + 1];
    model.means[3 * i + 2] = -model.means[3 * i + 2];
    model.quats[4 * i + 2] = -model.quats[4 * i + 2];
    model.quats[4 * i + 3] = -model.quats[4 * i + 3];
    for (std::size_t k = 0; k < coefficients; ++k)
      for (std::size_t c = 0; c < 3; ++c) model.sh[(i * coefficients + k) * 3 + c] *= signs[k];
  }
}

}  // namespace splat
