#include "splat/optim/masked_loss.hpp"

#include <string>

#include "splat/core/error.hpp"

namespace splat {

template <typename T>
LossValue masked_photometric_loss_core(const T* rendered, const T* target, const T* mask, int width, int height,
                                       T ssim_weight, T* v_rendered, std::vector<T>& masked,
                                       std::vector<T>& buffers) {
  const std::size_t pixels = std::size_t(width) * std::size_t(height), values = 3 * pixels;
  masked.resize(2 * values);
  T* masked_rendered = masked.data();
  T* masked_target = masked.data() + values;
  // Forward: both images through the mask.
  for (std::size_t p = 0; p < pixels; ++p)
    for (std::size_t c = 0; c < 3; ++c) {
      masked_rendered[3 * p + c] = rendered[3 * p + c] * mask[p];
      masked_target[3 * p + c] = target[3 * p + c] * mask[p];
    }
  const LossValue value = photometric_loss_core<T>(masked_rendered, masked_target, width, height, ssim_weight,
                                                   v_rendered, buffers);
  // Backward: the chain rule through r ⊙ m.
  if (v_rendered)
    for (std::size_t p = 0; p < pixels; ++p)
      for (std::size_t c = 0; c < 3; ++c) v_rendered[3 * p + c] *= mask[p];
  return value;
}

template LossValue masked_photometric_loss_core<float>(const float*, const float*, const float*, int, int, float,
                                                       float*, std::vector<float>&, std::vector<float>&);
template LossValue masked_photometric_loss_core<double>(const double*, const double*, const double*, int, int,
                                                        double, double*, std::vector<double>&,
                                                        std::vector<double>&);

LossValue masked_photometric_loss(const Image& rendered, const Image& target, const Image& mask,
                                  float ssim_weight, Image* v_rendered, MaskedLossScratch& scratch) {
  const auto shape = [](const Image& i) {
    return std::to_string(i.width) + "x" + std::to_string(i.height) + "x" + std::to_string(i.channels);
  };
  if (rendered.channels != 3 || target.channels != 3 || mask.channels != 1 || rendered.width != target.width ||
      rendered.height != target.height || mask.width != rendered.width || mask.height != rendered.height ||
      rendered.data.empty())
    throw ArgumentError("masked loss: rendered " + shape(rendered) + ", target " + shape(target) + " and mask " +
                        shape(mask) + " must be one non-empty [H, W, 3], [H, W, 3], [H, W, 1]");
  if (v_rendered) {
    v_rendered->width = rendered.width, v_rendered->height = rendered.height, v_rendered->channels = 3;
    v_rendered->data.resize(rendered.data.size());  // every value is overwritten
  }
  return masked_photometric_loss_core<float>(rendered.data.data(), target.data.data(), mask.data.data(),
                                             rendered.width, rendered.height, ssim_weight,
                                             v_rendered ? v_rendered->data.data() : nullptr,
                                             scratch.masked, scratch.ssim.buffers);
}

}  // namespace splat
