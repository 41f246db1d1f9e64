#include "splat/optim/photometric_loss.hpp"

#include <cmath>
#include <cstddef>
#include <functional>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include "splat/core/error.hpp"
#include "splat/optim/ssim.hpp"

namespace splat {
namespace {

constexpr int kLossChannels = 3;
// Leaf size of the deterministic reduction of L1: fixed, so the summation order depends on the
// image height only.
constexpr int kRowsPerLeaf = 8;

std::string shape_text(const Image& image) {
  return std::to_string(image.width) + "x" + std::to_string(image.height) + "x" +
         std::to_string(image.channels);
}

void check_pair(const char* what, const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels)
    throw ArgumentError(std::string(what) + ": images differ in shape (" + shape_text(a) +
                        " vs " + shape_text(b) + ")");
  if (a.width <= 0 || a.height <= 0 || a.channels <= 0)
    throw ArgumentError(std::string(what) + ": empty image (" + shape_text(a) + ")");
  for (const Image* image : {&a, &b})
    if (image->data.size() != image->pixel_count() * image->channels)
      throw ArgumentError(std::string(what) + ": image data holds " +
                          std::to_string(image->data.size()) + " values, not " +
                          shape_text(*image));
}

// Σ |r − t| over one row of `count` values, in double with eight interleaved accumulators (a
// fixed order that pipelines). With `v` not null, also writes v = slope·sign(r − t), the
// derivative of slope·|r − t|, taken as 0 at the kink.
template <typename T>
double l1_row(const T* __restrict r, const T* __restrict t, int count, T slope, T* __restrict v) {
  constexpr int kLanes = 8;
  double lanes[kLanes] = {};
  int i = 0;
  for (; i + kLanes <= count; i += kLanes)
    for (int j = 0; j < kLanes; ++j) lanes[j] += std::abs(double(r[i + j]) - double(t[i + j]));
  double sum = 0;
  for (int j = 0; j < kLanes; ++j) sum += lanes[j];
  for (; i < count; ++i) sum += std::abs(double(r[i]) - double(t[i]));
  if (v)
    for (int k = 0; k < count; ++k) {
      const T d = r[k] - t[k];  // its sign is exact: float subtraction is 0 only when r == t
      v[k] = d > 0 ? slope : (d < 0 ? -slope : T(0));
    }
  return sum;
}

}  // namespace

template <typename T>
LossValue photometric_loss_core(const T* rendered, const T* target, int width, int height,
                                T ssim_weight, T* v_rendered, std::vector<T>& buffers) {
  const int row_values = width * kLossChannels;
  const double n = double(row_values) * height;
  const double lambda = double(ssim_weight);
  // ∂L/∂r from the L1 term: (1 − λ)·sign(r − t)/n.
  const T l1_slope = T((1 - lambda) / n);
  const double l1_sum = tbb::parallel_deterministic_reduce(
      tbb::blocked_range<int>(0, height, kRowsPerLeaf), 0.0,
      [&](const tbb::blocked_range<int>& rows, double sum) {
        for (int y = rows.begin(); y != rows.end(); ++y) {
          const std::size_t offset = std::size_t(y) * row_values;
          sum += l1_row(rendered + offset, target + offset, row_values, l1_slope,
                        v_rendered ? v_rendered + offset : nullptr);
        }
        return sum;
      },
      std::plus<double>());

  const SsimShape shape{width, height, kLossChannels};
  LossValue value;
  value.l1 = l1_sum / n;
  value.ssim = ssim_forward(rendered, target, shape, v_rendered != nullptr, buffers);
  value.loss = (1 - lambda) * value.l1 + lambda * (1 - value.ssim);
  // ∂L/∂SSIM = −λ.
  if (v_rendered) ssim_vjp(shape, T(-lambda), v_rendered, buffers);
  return value;
}

LossValue photometric_loss(const Image& rendered, const Image& target, float ssim_weight,
                           Image* v_rendered, SsimScratch& scratch) {
  check_pair("photometric_loss", rendered, target);
  if (rendered.channels != kLossChannels)
    throw ArgumentError("photometric_loss: images have " + std::to_string(rendered.channels) +
                        " channels, expected 3");
  float* v = nullptr;
  if (v_rendered) {
    v_rendered->width = rendered.width;
    v_rendered->height = rendered.height;
    v_rendered->channels = rendered.channels;
    v_rendered->data.resize(rendered.data.size());  // every value is overwritten
    v = v_rendered->data.data();
  }
  return photometric_loss_core(rendered.data.data(), target.data.data(), rendered.width,
                               rendered.height, ssim_weight, v, scratch.buffers);
}

double ssim(const Image& a, const Image& b) {
  check_pair("ssim", a, b);
  std::vector<float> buffers;  // an evaluation metric: one allocation per call is fine
  return ssim_forward(a.data.data(), b.data.data(), SsimShape{a.width, a.height, a.channels},
                      /*keep_for_vjp=*/false, buffers);
}

template LossValue photometric_loss_core<float>(const float*, const float*, int, int, float,
                                                float*, std::vector<float>&);
template LossValue photometric_loss_core<double>(const double*, const double*, int, int, double,
                                                 double*, std::vector<double>&);

}  // namespace splat
