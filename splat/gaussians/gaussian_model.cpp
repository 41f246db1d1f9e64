#include "splat/gaussians/gaussian_model.hpp"

#include <string>

#include "splat/core/error.hpp"

namespace splat {

void GaussianModel::resize(std::size_t n) {
  means.resize(n * 3);
  log_scales.resize(n * 3);
  quats.resize(n * 4);
  opacity_logits.resize(n);
  sh.resize(n * sh_coefficients() * 3);
}

void GaussianModel::check_consistent() const {
  if (sh_degree < 0 || sh_degree > kMaxShDegree)
    throw ArgumentError("GaussianModel: SH degree " + std::to_string(sh_degree) +
                        " is outside 0.." + std::to_string(kMaxShDegree));
  const std::size_t n = size();
  if (means.size() != n * 3 || log_scales.size() != n * 3 || quats.size() != n * 4 ||
      sh.size() != n * sh_coefficients() * 3)
    throw ArgumentError("GaussianModel: parameter arrays disagree in length for " +
                        std::to_string(n) + " Gaussians");
}

}  // namespace splat
