#pragma once
// Every clamp and threshold of the Gaussian rasterizer, shared by its forward and backward
// passes and by the reference rasterizer. The values follow the official 3DGS rasterizer
// so that models trained there render identically here (docs/DESIGN.md, "Numerics").
// The clamp both methods share (kMaxAlpha) and the early stop (kMinTransmittance) belong to
// the compositor.
#include "splat/composite/composite.hpp"

namespace splat {

constexpr int kTileSize = 16;              // tiles are kTileSize x kTileSize pixels
constexpr float kNearPlane = 0.2f;         // Gaussians with camera z <= this are culled
constexpr float kCovarianceDilation = 0.3f;  // px² added to the 2D covariance diagonal
constexpr float kJacobianClamp = 1.3f;     // x/z, y/z clamped to ±this·tan(fov/2) in J
constexpr float kRadiusSigmas = 3.0f;      // screen radius = ceil(3·sqrt(λmax))
constexpr float kMinAlpha = 1.0f / 255.0f;  // samples with α below this are skipped
constexpr float kMinEigenGap = 0.1f;       // λ = mid ± sqrt(max(kMinEigenGap, mid² − det))

}  // namespace splat
