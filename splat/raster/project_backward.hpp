#pragma once
// Backward of stage 1: from each Gaussian's 2D-parameter gradients (summed over its tiles)
// to the gradients of its raw stored parameters.
#include <vector>

#include "splat/core/camera.hpp"
#include "splat/gaussians/gaussian_model.hpp"
#include "splat/gaussians/sh_gradient_factors.hpp"
#include "splat/raster/bin_sort.hpp"
#include "splat/raster/blend_backward.hpp"
#include "splat/raster/project.hpp"

namespace splat {

// ∂L/∂ of a view's camera-from-world rotation W (as a free 3 × 3 matrix) and translation t.
struct CameraPoseGradient {
  glm::mat3 rotation{0.0f};  // glm's [column][row]
  glm::vec3 translation{0.0f};
};

// Sums each Gaussian's overlap gradients (`overlap`'s written records; Gaussian i's are
// [bins.overlap_start[i], [i+1]), in the fixed order of its tile rectangle), then
// chains them through the colour (SH and its view direction), the opacity sigmoid, the
// conic inverse, the EWA covariance Σ' = J W Σ Wᵀ Jᵀ and the pixel projection to means,
// log-scales, quaternions (through their normalisation), opacity logits and SH coefficients.
// `grads` is resized like `model` and overwritten. `viewspace_grad_norm[i]` receives the norm
// of ∂L/∂(2D mean) in normalised device units (pixels × (W/2, H/2)), as the reference
// trainer accumulates it for densification; 0 for Gaussians that touch no tile.
// `blend_weight[i]` receives Σ Tα over all pixels (the overlaps' blend_weight summed).
// `camera_pose`, if given, receives ∂L/∂(the camera's pose) (camera_pose_vjp), summed over
// the Gaussians in fixed blocks and fixed order, so it too is the same for any thread count.
// `sh_factors`, if given, receives the SH coefficients' gradient in factored form
// (sh_gradient_factors.hpp) and `grads.sh` is then not written (it keeps whatever it held).
// The chain runs kLanes Gaussians at a time (lane_projection.hpp); the sum of each
// Gaussian's tile records stays one Gaussian at a time, in its rectangle's order.
void project_gaussians_backward(const GaussianModel& model, const Camera& camera, int sh_degree,
                                const TileBins& bins,
                                const OverlapGradients& overlap,
                                GaussianModel& grads, std::vector<float>& viewspace_grad_norm,
                                std::vector<float>& blend_weight,
                                CameraPoseGradient* camera_pose = nullptr,
                                ShGradientFactors* sh_factors = nullptr);

}  // namespace splat
