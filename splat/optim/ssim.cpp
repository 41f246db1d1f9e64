#include "splat/optim/ssim.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include "splat/core/error.hpp"

namespace splat {
namespace {

constexpr int R = kSsimRadius;
constexpr int kMoments = 5;   // the forward blurs x, y, x², y², xy
constexpr int kPartials = 3;  // and keeps ∂map/∂μx, ∂map/∂(G∗x²), ∂map/∂(G∗xy) for the backward
// Rows per band, the unit of parallel work. A band's row-blurred fields (the band and R rows of
// halo either side: 26·W·5 values) stay in the core's cache from the row pass to the column
// pass, instead of travelling through memory as whole-image planes; the halo rows' row pass is
// done by both neighbouring bands, identically. Fixed, so the summation order of the mean
// depends on the image height alone.
constexpr int kBandRows = 16;
constexpr int kBandSpan = kBandRows + 2 * R;
// Channel counts known at compile time let the compiler vectorise the interleaved loads and
// stores (shuffles instead of gathers); 0 means "read it at run time".
constexpr int kRuntimeChannels = 0;

// The flat buffer holds, in order:
//   partials   [C][3][H, W + 2R]   the saved state, zero-padded columns (only when kept)
//   one workspace per thread slot of the task arena:
//     input    [2][W + 2R]         one row of one channel of x and y, zero-padded
//     band     [5][kBandSpan, W]   one channel's row-blurred fields; row j is image row y0 − R + j
//     out      [C][kBandRows, W]   the band's map rows (forward) or gradient rows (backward)
struct Layout {
  int width = 0, height = 0, channels = 0;

  explicit Layout(SsimShape s) : width(s.width), height(s.height), channels(s.channels) {}
  std::size_t padded_width() const { return std::size_t(width) + 2 * R; }
  std::size_t partial_plane() const { return std::size_t(height) * padded_width(); }
  std::size_t partials_size(bool kept) const {
    return kept ? std::size_t(channels) * kPartials * partial_plane() : 0;
  }
  std::size_t band_field() const { return std::size_t(kBandSpan) * width; }
  std::size_t workspace_size() const {
    return 2 * padded_width() + kMoments * band_field() +
           std::size_t(channels) * kBandRows * width;
  }
};

template <typename T>
struct Saved {
  T* partials;
  Layout layout;
  // Row r of partial f of channel c, padded: column col is at index R + col. The three partials
  // of a row are partial_plane() apart.
  T* partial_row(int c, int f, int r) const {
    return partials + (std::size_t(c) * kPartials + f) * layout.partial_plane() +
           std::size_t(r) * layout.padded_width();
  }
};

template <typename T>
struct Workspace {
  T* input;  // [2][W + 2R]
  T* band;   // [5][kBandSpan, W]
  T* out;    // [C][kBandRows, W]
  Layout layout;
  T* input_row(int f) const { return input + f * layout.padded_width(); }
  T* band_row(int f, int j) const {
    return band + f * layout.band_field() + std::size_t(j) * layout.width;
  }
  T* out_row(int c, int i) const {
    return out + (std::size_t(c) * kBandRows + i) * layout.width;
  }
};

// Resizes `buffers` for the saved state and `slots` workspaces; the saved state comes first,
// so growing for more slots keeps it.
template <typename T>
void reserve_buffers(const Layout& layout, bool kept, int slots, std::vector<T>& buffers) {
  const std::size_t size =
      layout.partials_size(kept) + std::size_t(slots) * layout.workspace_size();
  if (buffers.size() < size) buffers.resize(size);
}

// The calling thread's workspace. Each thread runs one band to completion before taking
// another (a band spawns no nested work), so its slot's workspace is its own meanwhile.
template <typename T>
Workspace<T> this_threads_workspace(const Layout& layout, bool kept, int slots,
                                    std::vector<T>& buffers) {
  const int slot = tbb::this_task_arena::current_thread_index();
  if (slot < 0 || slot >= slots) throw std::logic_error("ssim: thread slot outside the arena");
  T* base = buffers.data() + layout.partials_size(kept) + slot * layout.workspace_size();
  Workspace<T> ws{base, nullptr, nullptr, layout};
  ws.band = base + 2 * layout.padded_width();
  ws.out = ws.band + kMoments * layout.band_field();
  return ws;
}

// Zeroes the R columns either side of a padded row.
template <typename T>
void zero_border_columns(T* padded_row, int width) {
  for (int k = 0; k < R; ++k) {
    padded_row[k] = T(0);
    padded_row[R + width + k] = T(0);
  }
}

// Channel c of one interleaved row [W, C] into a zero-padded row (column col at R + col).
template <typename T, int kChannels>
void load_padded_row(const T* __restrict in, int c, int width, int channels, T* __restrict out) {
  const int C = kChannels != kRuntimeChannels ? kChannels : channels;
  zero_border_columns(out, width);
  for (int col = 0; col < width; ++col) out[R + col] = in[std::size_t(col) * C + c];
}

// out[col, c] += scale · planes[c·channel_stride + col] over one interleaved row.
template <typename T, int kChannels>
void add_interleaved(const T* __restrict planes, std::size_t channel_stride, int width,
                     int channels, T scale, T* __restrict out) {
  const int C = kChannels != kRuntimeChannels ? kChannels : channels;
  for (int col = 0; col < width; ++col)
    for (int c = 0; c < C; ++c)
      out[std::size_t(col) * C + c] += scale * planes[c * channel_stride + col];
}

// Σ_k w_k·v_k over the window's taps, v_k = tap(k), in two partial sums (even and odd taps)
// so that consecutive multiply-adds do not all wait on one another. Which sum a tap joins is
// fixed, so the rounding is too. (Folding the symmetric taps in pairs, w_k = w_{2R−k}, trades
// five multiply-adds for five additions; it measured no faster here, so the plain sum stays.)
// Always inlined: the column loops vectorise only with it inside them. GCC inlines it anyway;
// clang under the sanitizers did not, and called it once per field and pixel (a third of a
// training test's time in the sanitizer suite).
template <typename T, typename Tap>
[[gnu::always_inline]] inline T window_sum(const std::array<T, kSsimWindow>& w, Tap tap) {
  T even = 0, odd = 0;
#pragma GCC unroll 16  // the whole window, so that the kernels' column loops vectorise
  for (int k = 0; k < kSsimWindow; ++k) {
    if (k % 2 == 0)
      even += w[k] * tap(k);
    else
      odd += w[k] * tap(k);
  }
  return even + odd;
}

// Row pass of the forward: the five fields x, y, x², y², xy of one padded row pair blurred
// (column col reads padded indices col .. col + 2R), the products formed on the fly so that
// only x and y are loaded; field f goes to out + f·out_stride. The kernels take restrict
// parameters, not locals, because GCC honours __restrict only there, and their column loops
// vectorise only when it knows outputs and inputs do not alias.
template <typename T>
void blur_moments_along_row(const T* __restrict x, const T* __restrict y, int width,
                            const std::array<T, kSsimWindow>& weights, T* __restrict out,
                            std::size_t out_stride) {
  const std::array<T, kSsimWindow> w = weights;  // a local copy the compiler keeps in registers
  for (int col = 0; col < width; ++col) {
    // Two partial sums per field, as in window_sum; w·x and w·y are shared by the products.
    T sx[2] = {0, 0}, sy[2] = {0, 0}, sxx[2] = {0, 0}, syy[2] = {0, 0}, sxy[2] = {0, 0};
#pragma GCC unroll 16  // the whole window, so that the column loop vectorises
    for (int k = 0; k < kSsimWindow; ++k) {
      const T a = x[col + k], b = y[col + k];
      const T wa = w[k] * a, wb = w[k] * b;
      sx[k % 2] += wa;
      sy[k % 2] += wb;
      sxx[k % 2] += wa * a;
      syy[k % 2] += wb * b;
      sxy[k % 2] += wa * b;
    }
    out[col] = sx[0] + sx[1];
    out[out_stride + col] = sy[0] + sy[1];
    out[2 * out_stride + col] = sxx[0] + sxx[1];
    out[3 * out_stride + col] = syy[0] + syy[1];
    out[4 * out_stride + col] = sxy[0] + sxy[1];
  }
}

// Row pass of the backward: the three partials' padded rows (partial f at in + f·in_stride)
// blurred into out + f·out_stride.
template <typename T>
void blur_partials_along_row(const T* __restrict in, std::size_t in_stride, int width,
                             const std::array<T, kSsimWindow>& weights, T* __restrict out,
                             std::size_t out_stride) {
  const std::array<T, kSsimWindow> w = weights;
  for (int col = 0; col < width; ++col) {
    // Written out per partial: as a loop over them, GCC vectorises that loop instead.
    const auto blurred = [&](int f) {
      return window_sum(w, [&](int k) { return in[f * in_stride + col + k]; });
    };
    out[col] = blurred(0);
    out[out_stride + col] = blurred(1);
    out[2 * out_stride + col] = blurred(2);
  }
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

// Column pass of the forward over one output row: tap k of field f is
// band[f·field_stride + k·tap_stride + col]; then the map and, with kKeepPartials, its
// partials (partial f at partials + f·partial_stride).
template <typename T, bool kKeepPartials>
void ssim_map_columns(const T* __restrict band, std::size_t field_stride, std::size_t tap_stride,
                      int width, const std::array<T, kSsimWindow>& weights, T* __restrict map,
                      T* __restrict partials, std::size_t partial_stride) {
  const std::array<T, kSsimWindow> w = weights;
  for (int col = 0; col < width; ++col) {
    const auto blurred = [&](int f) {
      return window_sum(w, [&](int k) { return band[f * field_stride + k * tap_stride + col]; });
    };
    const MapAtPixel<T> at = ssim_map_at(blurred(0), blurred(1), blurred(2), blurred(3), blurred(4));
    map[col] = at.map;
    if constexpr (kKeepPartials) {
      partials[col] = at.d_mu;
      partials[partial_stride + col] = at.d_exx;
      partials[2 * partial_stride + col] = at.d_exy;
    }
  }
}

// Column pass of the backward over one output row (taps as in ssim_map_columns), then the
// per-pixel combination g = G∗(∂m/∂μx) + 2x·G∗(∂m/∂Exx) + y·G∗(∂m/∂Exy).
template <typename T>
void ssim_gradient_columns(const T* __restrict band, std::size_t field_stride,
                           std::size_t tap_stride, int width,
                           const std::array<T, kSsimWindow>& weights, const T* __restrict x,
                           const T* __restrict y, T* __restrict g) {
  const std::array<T, kSsimWindow> w = weights;
  for (int col = 0; col < width; ++col) {
    const auto blurred = [&](int f) {
      return window_sum(w, [&](int k) { return band[f * field_stride + k * tap_stride + col]; });
    };
    g[col] = blurred(0) + 2 * x[col] * blurred(1) + y[col] * blurred(2);
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

// Forward over one band (image rows y0 .. y0 + kBandRows, clipped), every channel: the map,
// the partials if kept, and Σ map in double (channels in order, then rows in order).
template <typename T, int kChannels, bool kKeepPartials>
double forward_band(const T* x, const T* y, const Saved<T>& saved, const Workspace<T>& ws,
                    int y0, const std::array<T, kSsimWindow>& w) {
  const Layout& L = saved.layout;
  const int W = L.width, H = L.height, C = L.channels;
  const int y1 = std::min(y0 + kBandRows, H);
  const std::size_t row_values = std::size_t(W) * C;
  double sum = 0;
  for (int c = 0; c < C; ++c) {
    // Row pass over the band and its halo; rows outside the image are the conv2d's zeros.
    for (int j = 0; j < (y1 - y0) + 2 * R; ++j) {
      const int r = y0 - R + j;
      if (r < 0 || r >= H) {
        for (int f = 0; f < kMoments; ++f) std::fill_n(ws.band_row(f, j), W, T(0));
        continue;
      }
      load_padded_row<T, kChannels>(x + r * row_values, c, W, C, ws.input_row(0));
      load_padded_row<T, kChannels>(y + r * row_values, c, W, C, ws.input_row(1));
      blur_moments_along_row(ws.input_row(0), ws.input_row(1), W, w, ws.band_row(0, j),
                             L.band_field());
    }
    // Column pass: output row r reads band rows r − y0 .. r − y0 + 2R.
    for (int r = y0; r < y1; ++r) {
      T* partials = nullptr;
      if constexpr (kKeepPartials) {
        for (int f = 0; f < kPartials; ++f) zero_border_columns(saved.partial_row(c, f, r), W);
        partials = saved.partial_row(c, 0, r) + R;
      }
      T* map = ws.out_row(0, r - y0);
      ssim_map_columns<T, kKeepPartials>(ws.band_row(0, r - y0), L.band_field(), std::size_t(W),
                                         W, w, map, partials, L.partial_plane());
      sum += sum_in_double(map, W);
    }
  }
  return sum;
}

// Backward over one band, every channel, then v_x += scale · (n·∂SSIM/∂x) for its rows, where
//   ∂SSIM/∂x = (1/n) [G∗(∂m/∂μx) + 2x·G∗(∂m/∂Exx) + y·G∗(∂m/∂Exy)].
// Derivation: SSIM = (1/n) Σ_p m(p) with μx(p) = Σ_q G(p − q) x_q, Exx(p) = Σ_q G(p − q) x_q²,
// Exy(p) = Σ_q G(p − q) x_q y_q, so
//   ∂SSIM/∂x_q = (1/n) Σ_p G(p − q) [∂m/∂μx(p) + 2 x_q ∂m/∂Exx(p) + y_q ∂m/∂Exy(p)].
// Σ_p G(p − q) f(p) with p over the image only is the adjoint of the zero-padded blur; the
// window is symmetric, so it is the same zero-padded blur applied to f. The separable blur's
// adjoint runs its passes in reverse order, but as linear maps the row and column passes
// commute (they act on different axes of a rectangular zero padding), so rows-then-columns is
// reused; the two orders differ by rounding only.
template <typename T, int kChannels>
void backward_band(const T* x, const T* y, const Saved<T>& saved, const Workspace<T>& ws,
                   int y0, const std::array<T, kSsimWindow>& w, T scale, T* v_x) {
  const Layout& L = saved.layout;
  const int W = L.width, H = L.height, C = L.channels;
  const int y1 = std::min(y0 + kBandRows, H);
  const std::size_t row_values = std::size_t(W) * C;
  for (int c = 0; c < C; ++c) {
    for (int j = 0; j < (y1 - y0) + 2 * R; ++j) {
      const int r = y0 - R + j;
      if (r < 0 || r >= H) {
        for (int f = 0; f < kPartials; ++f) std::fill_n(ws.band_row(f, j), W, T(0));
        continue;
      }
      blur_partials_along_row(saved.partial_row(c, 0, r), L.partial_plane(), W, w,
                              ws.band_row(0, j), L.band_field());
    }
    for (int r = y0; r < y1; ++r) {
      load_padded_row<T, kChannels>(x + r * row_values, c, W, C, ws.input_row(0));
      load_padded_row<T, kChannels>(y + r * row_values, c, W, C, ws.input_row(1));
      ssim_gradient_columns(ws.band_row(0, r - y0), L.band_field(), std::size_t(W), W, w,
                            ws.input_row(0) + R, ws.input_row(1) + R, ws.out_row(c, r - y0));
    }
  }
  for (int r = y0; r < y1; ++r)
    add_interleaved<T, kChannels>(ws.out_row(0, r - y0), std::size_t(kBandRows) * W, W, C, scale,
                                  v_x + r * row_values);
}

int band_count(int height) { return (height + kBandRows - 1) / kBandRows; }

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
  const Layout layout(shape);
  const int slots = tbb::this_task_arena::max_concurrency();
  reserve_buffers(layout, keep_for_vjp, slots, buffers);
  const Saved<T> saved{buffers.data(), layout};
  const std::array<T, kSsimWindow> w = ssim_window_1d<T>();
  const bool three = shape.channels == 3;
  // One leaf per band and a fixed tree: the same additions in the same order for any threads.
  const double sum = tbb::parallel_deterministic_reduce(
      tbb::blocked_range<int>(0, band_count(shape.height), 1), 0.0,
      [&](const tbb::blocked_range<int>& bands, double partial_sum) {
        const Workspace<T> ws = this_threads_workspace(layout, keep_for_vjp, slots, buffers);
        for (int b = bands.begin(); b != bands.end(); ++b) {
          const int y0 = b * kBandRows;
          if (keep_for_vjp)
            partial_sum += three ? forward_band<T, 3, true>(x, y, saved, ws, y0, w)
                                 : forward_band<T, kRuntimeChannels, true>(x, y, saved, ws, y0, w);
          else
            partial_sum += three ? forward_band<T, 3, false>(x, y, saved, ws, y0, w)
                                 : forward_band<T, kRuntimeChannels, false>(x, y, saved, ws, y0, w);
        }
        return partial_sum;
      },
      std::plus<double>());
  return sum / (double(shape.width) * shape.height * shape.channels);
}

template <typename T>
void ssim_vjp(const T* x, const T* y, SsimShape shape, T v_ssim, T* v_x,
              std::vector<T>& buffers) {
  const Layout layout(shape);
  if (buffers.size() < layout.partials_size(true))
    throw ArgumentError("ssim_vjp: the buffers hold no forward pass that kept its partials");
  const int slots = tbb::this_task_arena::max_concurrency();
  reserve_buffers(layout, true, slots, buffers);
  const Saved<T> saved{buffers.data(), layout};
  const std::array<T, kSsimWindow> w = ssim_window_1d<T>();
  const T scale = T(double(v_ssim) / (double(shape.width) * shape.height * shape.channels));
  // Bands write disjoint rows of v_x.
  tbb::parallel_for(tbb::blocked_range<int>(0, band_count(shape.height), 1),
                    [&](const tbb::blocked_range<int>& bands) {
                      const Workspace<T> ws = this_threads_workspace(layout, true, slots, buffers);
                      for (int b = bands.begin(); b != bands.end(); ++b) {
                        const int y0 = b * kBandRows;
                        if (shape.channels == 3)
                          backward_band<T, 3>(x, y, saved, ws, y0, w, scale, v_x);
                        else
                          backward_band<T, kRuntimeChannels>(x, y, saved, ws, y0, w, scale, v_x);
                      }
                    });
}

template std::array<float, kSsimWindow> ssim_window_1d<float>();
template std::array<double, kSsimWindow> ssim_window_1d<double>();
template double ssim_forward<float>(const float*, const float*, SsimShape, bool,
                                    std::vector<float>&);
template double ssim_forward<double>(const double*, const double*, SsimShape, bool,
                                     std::vector<double>&);
template void ssim_vjp<float>(const float*, const float*, SsimShape, float, float*,
                              std::vector<float>&);
template void ssim_vjp<double>(const double*, const double*, SsimShape, double, double*,
                               std::vector<double>&);

}  // namespace splat
