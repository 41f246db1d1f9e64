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
// The unit of parallel work is a tile of output pixels. Within a tile, one channel at a time,
// the row pass walks down the tile's rows (and R rows of halo above and below), blurring each
// row once into a ring that holds the last kSsimWindow row-blurred rows of every field; as soon
// as a row enters, the column pass forms the output row 2R above it. Each ring row is stored
// twice, at slots s and s + kSsimWindow, so that the window's rows always lie one stride apart
// from any starting slot. A 64-column tile's ring (5 fields × 22 rows × 64 values, 28 KB in
// float) stays in the core's first-level cache, where the column pass reads each value 11
// times. Only the halo rows are blurred twice (by the two tiles they border), so tiles are tall.
// Every output value is the same sequence of operations whatever the tiling; the tiling fixes
// only the summation order of the mean, which depends on the image's shape alone.
constexpr int kTileRows = 64;
constexpr int kTileColumns = 64;
constexpr int kRingRows = 2 * kSsimWindow;
constexpr std::size_t kRingField = std::size_t(kRingRows) * kTileColumns;
// Channel counts known at compile time let the compiler vectorise the interleaved loads and
// stores (shuffles instead of gathers); 0 means "read it at run time".
constexpr int kRuntimeChannels = 0;

// The flat buffer holds, in order, planes of zero-padded rows (column col at index R + col):
//   inputs     [2][C][H, W + 2R]  x and y, one plane per channel, split once from the
//                                 interleaved images so that no tile deinterleaves a row again
//   partials   [C][3][H, W + 2R]  ∂map/∂μx, ∂map/∂(G∗x²), ∂map/∂(G∗xy) (only when kept)
// (the inputs and partials are the state the vjp consumes), then one workspace per thread slot
// of the task arena:
//     ring     [5][kRingRows, kTileColumns]  the last rows of one channel's row-blurred fields
//     out      [C][kTileRows, kTileColumns]  the map row (forward) or gradient rows (backward)
struct Layout {
  int width = 0, height = 0, channels = 0;

  explicit Layout(SsimShape s) : width(s.width), height(s.height), channels(s.channels) {}
  std::size_t padded_width() const { return std::size_t(width) + 2 * R; }
  std::size_t plane_size() const { return std::size_t(height) * padded_width(); }
  std::size_t planes_size(bool kept) const {
    return std::size_t(channels) * (2 + (kept ? kPartials : 0)) * plane_size();
  }
  std::size_t workspace_size() const {
    return kMoments * kRingField + std::size_t(channels) * kTileRows * kTileColumns;
  }
  int tiles_across() const { return (width + kTileColumns - 1) / kTileColumns; }
  int tile_count() const { return tiles_across() * ((height + kTileRows - 1) / kTileRows); }
};

// Output rows y0 .. y0 + rows and columns x0 .. x0 + columns; tiles are numbered row-major.
struct Tile {
  int x0 = 0, y0 = 0, columns = 0, rows = 0;

  Tile(const Layout& layout, int index) {
    x0 = index % layout.tiles_across() * kTileColumns;
    y0 = index / layout.tiles_across() * kTileRows;
    columns = std::min(kTileColumns, layout.width - x0);
    rows = std::min(kTileRows, layout.height - y0);
  }
};

template <typename T>
struct Planes {
  T* base;
  Layout layout;
  // Padded row r of plane p: column col is at index R + col.
  T* row(std::size_t p, int r) const {
    return base + p * layout.plane_size() + std::size_t(r) * layout.padded_width();
  }
  // Channel c of x (image 0) or y (image 1).
  T* input_row(int image, int c, int r) const {
    return row(std::size_t(image) * layout.channels + c, r);
  }
  // Partial f of channel c; the three partials of a row are plane_size() apart.
  T* partial_row(int c, int f, int r) const {
    return row(2 * std::size_t(layout.channels) + std::size_t(c) * kPartials + f, r);
  }
};

template <typename T>
struct Workspace {
  T* ring;  // [5][kRingRows, kTileColumns]
  T* out;   // [C][kTileRows, kTileColumns]
  T* ring_row(int f, int slot) const {
    return ring + f * kRingField + std::size_t(slot) * kTileColumns;
  }
  T* out_row(int c, int i) const {
    return out + (std::size_t(c) * kTileRows + i) * kTileColumns;
  }
};

// Resizes `buffers` for the planes and `slots` workspaces; the planes come first, so growing for
// more slots keeps them.
template <typename T>
void reserve_buffers(const Layout& layout, bool kept, int slots, std::vector<T>& buffers) {
  const std::size_t size =
      layout.planes_size(kept) + std::size_t(slots) * layout.workspace_size();
  if (buffers.size() < size) buffers.resize(size);
}

// The calling thread's workspace. Each thread runs one tile to completion before taking
// another (a tile spawns no nested work), so its slot's workspace is its own meanwhile.
template <typename T>
Workspace<T> this_threads_workspace(const Layout& layout, bool kept, int slots,
                                    std::vector<T>& buffers) {
  const int slot = tbb::this_task_arena::current_thread_index();
  if (slot < 0 || slot >= slots) throw std::logic_error("ssim: thread slot outside the arena");
  T* base = buffers.data() + layout.planes_size(kept) + slot * layout.workspace_size();
  return Workspace<T>{base, base + kMoments * kRingField};
}

// The ring slot that band row j (image row y0 − R + j) goes to; the window of output row i
// (image row y0 + i, band rows i .. i + 2R) starts at slot i % kSsimWindow and runs on into the
// twins.
int ring_slot(int band_row) { return band_row % kSsimWindow; }

// Copies the first `fields` fields' row at `slot` to its twin at slot + kSsimWindow.
template <typename T>
void mirror_ring_slot(const Workspace<T>& ws, int fields, int slot, int columns) {
  for (int f = 0; f < fields; ++f)
    std::copy_n(ws.ring_row(f, slot), columns, ws.ring_row(f, slot + kSsimWindow));
}

// A row outside the image: the conv2d's zeros, in the slot and its twin.
template <typename T>
void zero_ring_slot(const Workspace<T>& ws, int fields, int slot, int columns) {
  for (int f = 0; f < fields; ++f) {
    std::fill_n(ws.ring_row(f, slot), columns, T(0));
    std::fill_n(ws.ring_row(f, slot + kSsimWindow), columns, T(0));
  }
}

// Channel c of one interleaved row [W, C] into a zero-padded row (column col at R + col).
template <typename T, int kChannels>
void load_padded_row(const T* __restrict in, int c, int width, int channels, T* __restrict out) {
  const int C = kChannels != kRuntimeChannels ? kChannels : channels;
  std::fill_n(out, R, T(0));
  std::fill_n(out + R + width, R, T(0));
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
// vectorise only when it knows outputs and inputs do not alias; for the same reason they are
// never inlined (inlined into their caller, the restrict promise is lost with the parameters).
template <typename T>
[[gnu::noinline]]
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
[[gnu::noinline]]
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
// rows[f·field_stride + k·tap_stride + col]; then the map and, with kKeepPartials, its
// partials (partial f at partials + f·partial_stride).
template <typename T, bool kKeepPartials>
[[gnu::noinline]]
void ssim_map_columns(const T* __restrict rows, std::size_t field_stride, std::size_t tap_stride,
                      int width, const std::array<T, kSsimWindow>& weights, T* __restrict map,
                      T* __restrict partials, std::size_t partial_stride) {
  const std::array<T, kSsimWindow> w = weights;
  for (int col = 0; col < width; ++col) {
    const auto blurred = [&](int f) {
      return window_sum(w, [&](int k) { return rows[f * field_stride + k * tap_stride + col]; });
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
[[gnu::noinline]]
void ssim_gradient_columns(const T* __restrict rows, std::size_t field_stride,
                           std::size_t tap_stride, int width,
                           const std::array<T, kSsimWindow>& weights, const T* __restrict x,
                           const T* __restrict y, T* __restrict g) {
  const std::array<T, kSsimWindow> w = weights;
  for (int col = 0; col < width; ++col) {
    const auto blurred = [&](int f) {
      return window_sum(w, [&](int k) { return rows[f * field_stride + k * tap_stride + col]; });
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

// Channel c of every image row into the input planes: x to image 0, y to image 1.
template <typename T, int kChannels>
void split_into_planes(const T* x, const T* y, const Planes<T>& planes) {
  const Layout& L = planes.layout;
  const int W = L.width, C = L.channels;
  const std::size_t row_values = std::size_t(W) * C;
  tbb::parallel_for(tbb::blocked_range<int>(0, L.height), [&](const tbb::blocked_range<int>& rows) {
    for (int r = rows.begin(); r != rows.end(); ++r)
      for (int c = 0; c < C; ++c) {
        load_padded_row<T, kChannels>(x + r * row_values, c, W, C, planes.input_row(0, c, r));
        load_padded_row<T, kChannels>(y + r * row_values, c, W, C, planes.input_row(1, c, r));
      }
  });
}

// Forward over one tile, every channel: the map, the partials if kept, and Σ map in double
// (channels in order, then rows in order).
template <typename T, bool kKeepPartials>
double forward_tile(const Planes<T>& planes, const Workspace<T>& ws, const Tile& tile,
                    const std::array<T, kSsimWindow>& w) {
  const Layout& L = planes.layout;
  const int W = L.width, H = L.height, C = L.channels;
  T* map = ws.out_row(0, 0);
  double sum = 0;
  for (int c = 0; c < C; ++c) {
    // Band row j is image row y0 − R + j; once it is in the ring, output row j − 2R has its
    // whole window.
    for (int j = 0; j < tile.rows + 2 * R; ++j) {
      const int r = tile.y0 - R + j;
      if (r < 0 || r >= H) {
        zero_ring_slot(ws, kMoments, ring_slot(j), tile.columns);
      } else {
        // Padded index x0 is column x0 − R: the row pass's first tap.
        blur_moments_along_row(planes.input_row(0, c, r) + tile.x0,
                               planes.input_row(1, c, r) + tile.x0, tile.columns, w,
                               ws.ring_row(0, ring_slot(j)), kRingField);
        mirror_ring_slot(ws, kMoments, ring_slot(j), tile.columns);
      }
      const int i = j - 2 * R;
      if (i < 0) continue;
      T* partials = nullptr;
      if constexpr (kKeepPartials) {
        // The tiles at the image's edges zero the padding columns of their side.
        for (int f = 0; f < kPartials; ++f) {
          T* padded = planes.partial_row(c, f, tile.y0 + i);
          if (tile.x0 == 0) std::fill_n(padded, R, T(0));
          if (tile.x0 + tile.columns == W) std::fill_n(padded + R + W, R, T(0));
        }
        partials = planes.partial_row(c, 0, tile.y0 + i) + R + tile.x0;
      }
      ssim_map_columns<T, kKeepPartials>(ws.ring_row(0, ring_slot(i)), kRingField, kTileColumns,
                                         tile.columns, w, map, partials, L.plane_size());
      sum += sum_in_double(map, tile.columns);
    }
  }
  return sum;
}

// Backward over one tile, every channel, then v_x += scale · (n·∂SSIM/∂x) for its pixels,
// where
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
void backward_tile(const Planes<T>& planes, const Workspace<T>& ws, const Tile& tile,
                   const std::array<T, kSsimWindow>& w, T scale, T* v_x) {
  const Layout& L = planes.layout;
  const int W = L.width, H = L.height, C = L.channels;
  for (int c = 0; c < C; ++c) {
    for (int j = 0; j < tile.rows + 2 * R; ++j) {
      const int r = tile.y0 - R + j;
      if (r < 0 || r >= H) {
        zero_ring_slot(ws, kPartials, ring_slot(j), tile.columns);
      } else {
        blur_partials_along_row(planes.partial_row(c, 0, r) + tile.x0, L.plane_size(),
                                tile.columns, w, ws.ring_row(0, ring_slot(j)), kRingField);
        mirror_ring_slot(ws, kPartials, ring_slot(j), tile.columns);
      }
      const int i = j - 2 * R;
      if (i < 0) continue;
      const int row = tile.y0 + i;
      ssim_gradient_columns(ws.ring_row(0, ring_slot(i)), kRingField, kTileColumns, tile.columns,
                            w, planes.input_row(0, c, row) + R + tile.x0,
                            planes.input_row(1, c, row) + R + tile.x0, ws.out_row(c, i));
    }
  }
  const std::size_t row_values = std::size_t(W) * C;
  for (int i = 0; i < tile.rows; ++i)
    add_interleaved<T, kChannels>(ws.out_row(0, i), std::size_t(kTileRows) * kTileColumns,
                                  tile.columns, C, scale,
                                  v_x + (tile.y0 + i) * row_values + std::size_t(tile.x0) * C);
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
  const Layout layout(shape);
  const int slots = tbb::this_task_arena::max_concurrency();
  reserve_buffers(layout, keep_for_vjp, slots, buffers);
  const Planes<T> planes{buffers.data(), layout};
  if (shape.channels == 3)
    split_into_planes<T, 3>(x, y, planes);
  else
    split_into_planes<T, kRuntimeChannels>(x, y, planes);
  const std::array<T, kSsimWindow> w = ssim_window_1d<T>();
  // One leaf per tile and a fixed tree: the same additions in the same order for any threads.
  const double sum = tbb::parallel_deterministic_reduce(
      tbb::blocked_range<int>(0, layout.tile_count(), 1), 0.0,
      [&](const tbb::blocked_range<int>& tiles, double partial_sum) {
        const Workspace<T> ws = this_threads_workspace(layout, keep_for_vjp, slots, buffers);
        for (int index = tiles.begin(); index != tiles.end(); ++index) {
          const Tile tile(layout, index);
          partial_sum += keep_for_vjp ? forward_tile<T, true>(planes, ws, tile, w)
                                      : forward_tile<T, false>(planes, ws, tile, w);
        }
        return partial_sum;
      },
      std::plus<double>());
  return sum / (double(shape.width) * shape.height * shape.channels);
}

template <typename T>
void ssim_vjp(SsimShape shape, T v_ssim, T* v_x, std::vector<T>& buffers) {
  const Layout layout(shape);
  if (buffers.size() < layout.planes_size(true))
    throw ArgumentError("ssim_vjp: the buffers hold no forward pass that kept its partials");
  const int slots = tbb::this_task_arena::max_concurrency();
  reserve_buffers(layout, true, slots, buffers);
  const Planes<T> planes{buffers.data(), layout};
  const std::array<T, kSsimWindow> w = ssim_window_1d<T>();
  const T scale = T(double(v_ssim) / (double(shape.width) * shape.height * shape.channels));
  // Tiles write disjoint pixels of v_x.
  tbb::parallel_for(tbb::blocked_range<int>(0, layout.tile_count(), 1),
                    [&](const tbb::blocked_range<int>& tiles) {
                      const Workspace<T> ws = this_threads_workspace(layout, true, slots, buffers);
                      for (int index = tiles.begin(); index != tiles.end(); ++index) {
                        const Tile tile(layout, index);
                        if (shape.channels == 3)
                          backward_tile<T, 3>(planes, ws, tile, w, scale, v_x);
                        else
                          backward_tile<T, kRuntimeChannels>(planes, ws, tile, w, scale, v_x);
                      }
                    });
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
