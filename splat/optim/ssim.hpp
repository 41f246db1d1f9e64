#pragma once
// SSIM, forward and backward side by side, generic over the scalar (float for training and
// evaluation, double for the tests' finite differences). The definition is the official 3DGS
// one (utils/loss_utils.py): per channel, an 11×11 Gaussian window (σ = 1.5) applied as a
// conv2d with zero padding 5, so near the border the local statistics include the zeros and
// the window is not renormalised.
//   μx = G∗x, μy = G∗y, σx² = G∗x² − μx², σy² = G∗y² − μy², σxy = G∗(xy) − μx μy
//   map = (2 μx μy + C1)(2 σxy + C2) / ((μx² + μy² + C1)(σx² + σy² + C2))
//   SSIM = mean of the map over all pixels and channels
// Images are interleaved [height, width, channels]. The blur is separable (an 11-tap pass along
// rows, then one along columns) and runs in parallel over tiles of pixels, each tile's
// row-blurred fields staying in the first-level cache for its column pass. Every value is computed by one fixed sequence of
// operations and the mean is reduced in a fixed order, so results are bit-identical for any
// thread count.
#include <array>
#include <vector>

namespace splat {

constexpr int kSsimRadius = 5;                    // conv2d padding: window is 11×11
constexpr int kSsimWindow = 2 * kSsimRadius + 1;  // taps per 1D pass
constexpr double kSsimSigma = 1.5;
constexpr double kSsimC1 = 0.01 * 0.01;  // (K1·L)² with K1 = 0.01, dynamic range L = 1
constexpr double kSsimC2 = 0.03 * 0.03;  // (K2·L)² with K2 = 0.03

// exp(−(i − R)² / (2σ²)) normalised to sum 1, computed in double and rounded once to T.
// The 2D window is its outer product.
template <typename T>
std::array<T, kSsimWindow> ssim_window_1d();

struct SsimShape {
  int width = 0, height = 0, channels = 0;
};

// Mean SSIM of x against y (both [height, width, channels]). With `keep_for_vjp` it leaves in
// `buffers` what ssim_vjp consumes (the saved state): x and y split into planes, and the
// per-pixel partial derivatives of the map. `buffers` also holds one workspace per thread of
// the current task arena; it is resized as needed and allocates nothing once its capacity
// suffices. Shapes are not checked here (the public wrappers do that).
template <typename T>
double ssim_forward(const T* x, const T* y, SsimShape shape, bool keep_for_vjp,
                    std::vector<T>& buffers);

// v_x += v_ssim · ∂SSIM/∂x, y held constant; v_x is [height, width, channels], and `buffers`
// as ssim_forward(x, y, shape, /*keep_for_vjp=*/true, buffers) left them (x and y are read from
// there). The saved state is left intact, so it may be called again.
template <typename T>
void ssim_vjp(SsimShape shape, T v_ssim, T* v_x, std::vector<T>& buffers);

// v_x += v_ssim · ∂SSIM/∂x, y held constant; v_x is [height, width, channels]. x, y and `buffers`
// as ssim_forward(x, y, shape, /*keep_for_vjp=*/true, buffers) left them. The saved state is
// left intact, so it may be called again.
template <typename T>
void ssim_vjp(const T* x, const T* y, SsimShape shape, T v_ssim, T* v_x,
              std::vector<T>& buffers);

}  // namespace splat
