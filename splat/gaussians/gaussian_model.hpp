#pragma once
// The Gaussian model as a structure of arrays. Parameters are stored raw, exactly as the
// standard 3DGS PLY stores them; activations are applied on use (DESIGN.md):
//   scale = exp(log_scale), opacity = sigmoid(opacity_logit), rotation = normalize(quat),
//   colour = SH(dir) + 0.5 clamped at 0.
#include <cstddef>
#include <vector>

namespace splat {

constexpr int kMaxShDegree = 3;
// Number of SH coefficients per colour channel for a degree: (degree + 1)^2.
constexpr int sh_coefficient_count(int degree) { return (degree + 1) * (degree + 1); }

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
  // Resizes every array for n Gaussians at the current SH degree (new entries zero).
  void resize(std::size_t n);
  // Throws ArgumentError if the arrays disagree in length or the degree is out of range.
  void check_consistent() const;
};

}  // namespace splat
