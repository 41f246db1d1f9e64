#include "splat/optim/ssim.hpp"

#include <cmath>
#include <cstddef>
#include <functional>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "splat/core/error.hpp"

namespace splat {
namespace {

constexpr int R = kSsimRadius;
// Leaf size of the deterministic reduction. Fixed, so the summation tree (and therefore the
// rounding of the mean) depends on the image height only, never on the thread count.
constexpr int kRowsPerLeaf = 8;
// The forward keeps three per-pixel partials of the map (see ssim_map_row).
constexpr int kPartials = 3;
// The forward blurs five fields: x, y, x², y², xy.
constexpr int kMoments = 5;

// Where each buffer lives inside the flat scratch vector.
template <typename T>
struct Planes {
  int width = 0, height = 0, channels = 0;
  int padded_width = 0;   // W + 2R: R zero columns either side, so row passes need no tests
  int padded_height = 0;  // H + 2R: R zero rows above and below, so column passes need none
  T* x = nullptr;         // [C][H, W + 2R] the inputs, de-interleaved
  T* y = nullptr;         // [C][H, W + 2R]
  T* rows = nullptr;      // [5][H + 2R, W] one channel's row-blurred fields
  T* scalar = nullptr;    // [C][H, W] the map (forward) or the gradient (backward)
  T* partials = nullptr;  // [C][3][H, W + 2R] ∂map/∂μx, ∂map/∂(G∗x²), ∂map/∂(G∗xy)

  std::size_t padded_cols_plane() const { return std::size_t(height) * padded_width; }
  std::size_t padded_rows_plane() const { return std::size_t(padded_height) * width; }
  T* x_row(int c, int r) const { return x + c * padded_cols_plane() + std::size_t(r) * padded_width; }
  T* y_row(int c, int r) const { return y + c * padded_cols_plane() + std::size_t(r) * padded_width; }
  // Row-blurred field f, image row r (rows −R..H−1+R exist; the outer ones are zero).
  T* blurred_row(int f, int r) const {
    return rows + f * padded_rows_plane() + std::size_t(r + R) * width;
  }
  T* partial_row(int c, int p, int r) const {
    return partials + (std::size_t(c) * kPartials + p) * padded_cols_plane() +
           std::size_t(r) * padded_width;
  }
  std::size_t plain_plane() const { return std::size_t(height) * width; }
  T* scalar_row(int c, int r) const { return scalar + c * plain_plane() + std::size_t(r) * width; }
};

template <typename T>
std::size_t required_size(SsimShape s, bool with_partials) {
  const std::size_t padded_cols = std::size_t(s.height) * (s.width + 2 * R);
  const std::size_t padded_rows = std::size_t(s.height + 2 * R) * s.width;
  return 2 * s.channels * padded_cols + kMoments * padded_rows +
         std::size_t(s.channels) * s.height * s.width +
         (with_partials ? kPartials * s.channels * padded_cols : 0);
}

// Carves `buffers` (already at least required_size long) into planes. The partials come last,
// so the forward-only layout is a prefix of the full one.
template <typename T>
Planes<T> carve(SsimShape s, std::vector<T>& buffers, bool with_partials) {
  Planes<T> p;
  p.width = s.width;
  p.height = s.height;
  p.channels = s.channels;
  p.padded_width = s.width + 2 * R;
  p.padded_height = s.height + 2 * R;
  T* next = buffers.data();
  p.x = next;
  next += s.channels * p.padded_cols_plane();
  p.y = next;
  next += s.channels * p.padded_cols_plane();
  p.rows = next;
  next += kMoments * p.padded_rows_plane();
  p.scalar = next;
  next += s.channels * p.plain_plane();
  if (with_partials) p.partials = next;
  return p;
}

// The reused row-blur region's border rows must read as zero (they stand for the conv2d's zero
// padding); nothing ever writes them, but a buffer reused at another shape holds stale values.
template <typename T>
void zero_border_rows(const Planes<T>& p) {
  for (int f = 0; f < kMoments; ++f)
    for (int k = 1; k <= R; ++k)
      for (int col = 0; col < p.width; ++col) {
        p.blurred_row(f, -k)[col] = T(0);
        p.blurred_row(f, p.height - 1 + k)[col] = T(0);
      }
}

// Zeroes the R columns either side of a padded row.
template <typename T>
void zero_border_columns(T* padded_row, int width) {
  for (int k = 0; k < R; ++k) {
    padded_row[k] = T(0);
    padded_row[R + width + k] = T(0);
  }
}

// Channel counts known at compile time let the compiler vectorise the interleaved loads and
// stores (shuffles instead of gathers); 0 means "read it at run time".
constexpr int kRuntimeChannels = 0;

// One interleaved row [W, C] into C planes, plane c at planes + c·channel_stride.
template <typename T, int kChannels>
void deinterleave(const T* __restrict in, int width, int channels, std::size_t channel_stride,
                  T* __restrict planes) {
  const int C = kChannels != kRuntimeChannels ? kChannels : channels;
  for (int col = 0; col < width; ++col)
    for (int c = 0; c < C; ++c) planes[c * channel_stride + col] = in[std::size_t(col) * C + c];
}

// out[col, c] += scale · planes[c][col] for one interleaved row.
template <typename T, int kChannels>
void add_interleaved(const T* __restrict planes, std::size_t channel_stride, int width,
                     int channels, T scale, T* __restrict out) {
  const int C = kChannels != kRuntimeChannels ? kChannels : channels;
  for (int col = 0; col < width; ++col)
    for (int c = 0; c < C; ++c) out[std::size_t(col) * C + c] += scale * planes[c * channel_stride + col];
}

// Row r of every channel of x and y, from interleaved into the padded planes.
template <typename T, int kChannels>
void deinterleave_row(const T* x, const T* y, const Planes<T>& p, int r) {
  const int W = p.width, C = p.channels;
  const std::size_t offset = std::size_t(r) * W * C;
  deinterleave<T, kChannels>(x + offset, W, C, p.padded_cols_plane(), p.x_row(0, r) + R);
  deinterleave<T, kChannels>(y + offset, W, C, p.padded_cols_plane(), p.y_row(0, r) + R);
  for (int c = 0; c < C; ++c) {
    zero_border_columns(p.x_row(c, r), W);
    zero_border_columns(p.y_row(c, r), W);
  }
}

// Horizontal pass of the forward: the five fields x, y, x², y², xy blurred along one row.
// Inputs are padded rows (index R + col is column col); the products are formed on the fly.
template <typename T>
void blur_moments_along_row(const T* __restrict xr, const T* __restrict yr, int width,
                            const std::array<T, kSsimWindow>& weights, T* __restrict out_x,
                            T* __restrict out_y, T* __restrict out_xx, T* __restrict out_yy,
                            T* __restrict out_xy) {
  const std::array<T, kSsimWindow> w = weights;  // a local copy the compiler can keep in registers
  for (int col = 0; col < width; ++col) {
    T sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
#pragma GCC unroll 16  // the whole window, so that the column loop vectorises
    for (int k = 0; k < kSsimWindow; ++k) {
      const T a = xr[col + k], b = yr[col + k];
      const T wa = w[k] * a, wb = w[k] * b;
      sx += wa;
      sy += wb;
      sxx += wa * a;
      syy += wb * b;
      sxy += wa * b;
    }
    out_x[col] = sx;
    out_y[col] = sy;
    out_xx[col] = sxx;
    out_yy[col] = syy;
    out_xy[col] = sxy;
  }
}

// Horizontal pass of the backward: one padded row blurred.
template <typename T>
void blur_along_row(const T* __restrict in, int width, const std::array<T, kSsimWindow>& weights,
                    T* __restrict out) {
  const std::array<T, kSsimWindow> w = weights;
  for (int col = 0; col < width; ++col) {
    T s = 0;
#pragma GCC unroll 16  // the whole window, so that the column loop vectorises
    for (int k = 0; k < kSsimWindow; ++k) s += w[k] * in[col + k];
    out[col] = s;
  }
}

// Σ of a row in double, with eight interleaved accumulators so the additions pipeline; the
// order is fixed by the row's length alone.
template <typename T>
double sum_in_double(const T* v, int n) {
  constexpr int kLanes = 8;
  double lanes[kLanes] = {};
  int i = 0;
  for (; i + kLanes <= n; i += kLanes)
    for (int j = 0; j < kLanes; ++j) lanes[j] += double(v[i + j]);
  double sum = 0;
  for (int j = 0; j < kLanes; ++j) sum += lanes[j];
  for (; i < n; ++i) sum += double(v[i]);
  return sum;
}

// The SSIM map at one pixel from the five blurred fields, and the map's partial derivatives
// with respect to the three fields x enters (μx, Exx = G∗x², Exy = G∗xy).
//
// Derivation. With Eyy = G∗y²,
//   A1 = 2 μx μy + C1,  A2 = 2 (Exy − μx μy) + C2,
//   B1 = μx² + μy² + C1, B2 = (Exx − μx²) + (Eyy − μy²) + C2,  D = B1 B2 (> 0),
//   m  = A1 A2 / D.
// y is constant. Holding the other fields fixed:
//   ∂(A1 A2)/∂μx = 2μy·A2 + A1·(−2μy) = 2μy (A2 − A1)
//   ∂D/∂μx       = 2μx·B2 + B1·(−2μx) = 2μx (B2 − B1)
//   ∂m/∂μx  = [2μy (A2 − A1) − m·2μx (B2 − B1)] / D
//   ∂m/∂Exx = −A1 A2 B1 / D² = −m B1 / D       (only B2 depends on Exx, with slope 1)
//   ∂m/∂Exy = 2 A1 / D                          (only A2 depends on Exy, with slope 2)
// These are written without dividing by A1 or A2, which may be zero.
template <typename T>
struct MapAtPixel {
  T map, d_mu, d_exx, d_exy;
};

template <typename T>
inline MapAtPixel<T> ssim_map_at(T mx, T my, T exx, T eyy, T exy) {
  const T c1 = T(kSsimC1), c2 = T(kSsimC2);
  const T mxx = mx * mx, myy = my * my, mxy = mx * my;
  const T a1 = 2 * mxy + c1;
  const T a2 = 2 * (exy - mxy) + c2;
  const T b1 = mxx + myy + c1;
  const T b2 = (exx - mxx) + (eyy - myy) + c2;
  const T inv_d = T(1) / (b1 * b2);
  const T m = a1 * a2 * inv_d;
  return {m, 2 * (my * (a2 - a1) - m * mx * (b2 - b1)) * inv_d, -m * b1 * inv_d,
          2 * a1 * inv_d};
}

// Vertical pass of the forward over one output row: tap k of field f is b_f[k·stride + col]
// (the row-blurred rows r − R .. r + R), then the map and, with kKeepPartials, its partials.
// A kernel of its own because GCC honours __restrict on parameters, not on locals, and the
// column loop vectorises only when it knows the outputs do not alias the inputs.
template <typename T, bool kKeepPartials>
void ssim_map_columns(const T* __restrict bx, const T* __restrict by, const T* __restrict bxx,
                      const T* __restrict byy, const T* __restrict bxy, std::size_t stride,
                      int width, const std::array<T, kSsimWindow>& weights, T* __restrict map,
                      T* __restrict d_mu, T* __restrict d_exx, T* __restrict d_exy) {
  const std::array<T, kSsimWindow> w = weights;
  for (int col = 0; col < width; ++col) {
    T mx = 0, my = 0, exx = 0, eyy = 0, exy = 0;
#pragma GCC unroll 16  // the whole window, so that the column loop vectorises
    for (int k = 0; k < kSsimWindow; ++k) {
      const std::size_t i = k * stride + col;
      mx += w[k] * bx[i];
      my += w[k] * by[i];
      exx += w[k] * bxx[i];
      eyy += w[k] * byy[i];
      exy += w[k] * bxy[i];
    }
    const MapAtPixel<T> at = ssim_map_at(mx, my, exx, eyy, exy);
    map[col] = at.map;
    if constexpr (kKeepPartials) {
      d_mu[col] = at.d_mu;
      d_exx[col] = at.d_exx;
      d_exy[col] = at.d_exy;
    }
  }
}

// Image row r of channel c: the map (into p.scalar), the partials if kept, and Σ map in double.
template <typename T, bool kKeepPartials>
double ssim_map_row(const Planes<T>& p, int c, int r, const std::array<T, kSsimWindow>& w) {
  const int W = p.width;
  T* d[kPartials] = {nullptr, nullptr, nullptr};
  if constexpr (kKeepPartials)
    for (int f = 0; f < kPartials; ++f) {
      T* row = p.partial_row(c, f, r);
      zero_border_columns(row, W);
      d[f] = row + R;
    }
  T* map = p.scalar_row(c, r);
  ssim_map_columns<T, kKeepPartials>(p.blurred_row(0, r - R), p.blurred_row(1, r - R),
                                     p.blurred_row(2, r - R), p.blurred_row(3, r - R),
                                     p.blurred_row(4, r - R), std::size_t(W), W, w, map, d[0],
                                     d[1], d[2]);
  return sum_in_double(map, W);
}

// Vertical pass of the backward over one output row (taps as in ssim_map_columns), then the
// per-pixel combination g = G∗(∂m/∂μx) + 2x·G∗(∂m/∂Exx) + y·G∗(∂m/∂Exy).
template <typename T>
void ssim_gradient_columns(const T* __restrict b_mu, const T* __restrict b_xx,
                           const T* __restrict b_xy, std::size_t stride, int width,
                           const std::array<T, kSsimWindow>& weights, const T* __restrict x,
                           const T* __restrict y, T* __restrict g) {
  const std::array<T, kSsimWindow> w = weights;
  for (int col = 0; col < width; ++col) {
    T g_mu = 0, g_xx = 0, g_xy = 0;
#pragma GCC unroll 16  // the whole window, so that the column loop vectorises
    for (int k = 0; k < kSsimWindow; ++k) {
      const std::size_t i = k * stride + col;
      g_mu += w[k] * b_mu[i];
      g_xx += w[k] * b_xx[i];
      g_xy += w[k] * b_xy[i];
    }
    g[col] = g_mu + 2 * x[col] * g_xx + y[col] * g_xy;
  }
}

// Image row r of channel c of the backward, into p.scalar: n·∂SSIM/∂x, where
//   ∂SSIM/∂x = (1/n) [G∗(∂m/∂μx) + 2x·G∗(∂m/∂Exx) + y·G∗(∂m/∂Exy)].
// Derivation: SSIM = (1/n) Σ_p m(p) with μx(p) = Σ_q G(p − q) x_q, Exx(p) = Σ_q G(p − q) x_q²,
// Exy(p) = Σ_q G(p − q) x_q y_q, so
//   ∂SSIM/∂x_q = (1/n) Σ_p G(p − q) [∂m/∂μx(p) + 2 x_q ∂m/∂Exx(p) + y_q ∂m/∂Exy(p)].
// Σ_p G(p − q) f(p) with p over the image only is the adjoint of the zero-padded blur; the
// window is symmetric, so it is the same zero-padded blur applied to f. The separable blur's
// adjoint runs its passes in reverse order, but the row and column passes commute exactly
// (they act on different axes of a rectangular zero padding), so rows-then-columns is reused.
template <typename T>
void ssim_gradient_row(const Planes<T>& p, int c, int r, const std::array<T, kSsimWindow>& w) {
  const int W = p.width;
  ssim_gradient_columns(p.blurred_row(0, r - R), p.blurred_row(1, r - R),
                        p.blurred_row(2, r - R), std::size_t(W), W, w, p.x_row(c, r) + R,
                        p.y_row(c, r) + R, p.scalar_row(c, r));
}

template <typename T, bool kKeepPartials>
double ssim_channel_sum(const Planes<T>& p, int c, const std::array<T, kSsimWindow>& w) {
  const int H = p.height;
  tbb::parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& rows) {
    for (int r = rows.begin(); r != rows.end(); ++r)
      blur_moments_along_row(p.x_row(c, r), p.y_row(c, r), p.width, w, p.blurred_row(0, r),
                             p.blurred_row(1, r), p.blurred_row(2, r), p.blurred_row(3, r),
                             p.blurred_row(4, r));
  });
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<int>(0, H, kRowsPerLeaf), 0.0,
      [&](const tbb::blocked_range<int>& rows, double sum) {
        for (int r = rows.begin(); r != rows.end(); ++r)
          sum += ssim_map_row<T, kKeepPartials>(p, c, r, w);
        return sum;
      },
      std::plus<double>());
}

}  // namespace

template <typename T>
std::array<T, kSsimWindow> ssim_window_1d() {
  std::array<double, kSsimWindow> g{};
  double total = 0;
  for (int i = 0; i < kSsimWindow; ++i) {
    const double d = i - R;
    g[i] = std::exp(-d * d / (2 * kSsimSigma * kSsimSigma));
    total += g[i];
  }
  std::array<T, kSsimWindow> w{};
  for (int i = 0; i < kSsimWindow; ++i) w[i] = T(g[i] / total);
  return w;
}

template <typename T>
double ssim_forward(const T* x, const T* y, SsimShape shape, bool keep_for_vjp,
                    std::vector<T>& buffers) {
  buffers.resize(required_size<T>(shape, keep_for_vjp));
  const Planes<T> p = carve(shape, buffers, keep_for_vjp);
  const std::array<T, kSsimWindow> w = ssim_window_1d<T>();
  zero_border_rows(p);
  tbb::parallel_for(tbb::blocked_range<int>(0, shape.height),
                    [&](const tbb::blocked_range<int>& rows) {
                      for (int r = rows.begin(); r != rows.end(); ++r)
                        if (shape.channels == 3)
                          deinterleave_row<T, 3>(x, y, p, r);
                        else
                          deinterleave_row<T, kRuntimeChannels>(x, y, p, r);
                    });
  double sum = 0;  // channels in order: the reduction's shape is fixed
  for (int c = 0; c < shape.channels; ++c)
    sum += keep_for_vjp ? ssim_channel_sum<T, true>(p, c, w) : ssim_channel_sum<T, false>(p, c, w);
  return sum / (double(shape.width) * shape.height * shape.channels);
}

template <typename T>
void ssim_vjp(SsimShape shape, T v_ssim, T* v_x, std::vector<T>& buffers) {
  if (buffers.size() < required_size<T>(shape, true))
    throw ArgumentError("ssim_vjp: the buffers hold no forward pass that kept its partials");
  const Planes<T> p = carve(shape, buffers, true);
  const std::array<T, kSsimWindow> w = ssim_window_1d<T>();
  const T scale = T(double(v_ssim) / (double(shape.width) * shape.height * shape.channels));
  // The row-blur region's border rows are still zero from the forward: its passes write rows
  // 0..H−1 only.
  for (int c = 0; c < shape.channels; ++c) {
    tbb::parallel_for(tbb::blocked_range<int>(0, shape.height),
                      [&](const tbb::blocked_range<int>& rows) {
                        for (int r = rows.begin(); r != rows.end(); ++r)
                          for (int f = 0; f < kPartials; ++f)
                            blur_along_row(p.partial_row(c, f, r), p.width, w, p.blurred_row(f, r));
                      });
    // The last channel's pass also adds each finished row of every channel into v_x: the
    // earlier channels' rows are complete (their passes have returned).
    const bool last = c == shape.channels - 1;
    tbb::parallel_for(tbb::blocked_range<int>(0, shape.height),
                      [&](const tbb::blocked_range<int>& rows) {
                        for (int r = rows.begin(); r != rows.end(); ++r) {
                          ssim_gradient_row(p, c, r, w);
                          if (!last) continue;
                          T* out = v_x + std::size_t(r) * shape.width * shape.channels;
                          if (shape.channels == 3)
                            add_interleaved<T, 3>(p.scalar_row(0, r), p.plain_plane(), p.width,
                                                  3, scale, out);
                          else
                            add_interleaved<T, kRuntimeChannels>(p.scalar_row(0, r),
                                                                 p.plain_plane(), p.width,
                                                                 shape.channels, scale, out);
                        }
                      });
  }
}

template std::array<float, kSsimWindow> ssim_window_1d<float>();
template std::array<double, kSsimWindow> ssim_window_1d<double>();
template double ssim_forward<float>(const float*, const float*, SsimShape, bool,
                                    std::vector<float>&);
template double ssim_forward<double>(const double*, const double*, SsimShape, bool,
                                     std::vector<double>&);
template void ssim_vjp<float>(SsimShape, float, float*, std::vector<float>&);
template void ssim_vjp<double>(SsimShape, double, double*, std::vector<double>&);

}  // namespace splat
