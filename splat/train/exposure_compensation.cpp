#include "splat/train/exposure_compensation.hpp"

namespace splat {

ExposureCompensation::ExposureCompensation(std::size_t views)
    : adam_(views, {kExposureValues}, {0.9, 0.999, 1e-8}, "exposure maps") {}

void ExposureCompensation::apply(std::size_t view, const Image& rendered, Image& out) const {
  if (out.width != rendered.width || out.height != rendered.height || out.channels != rendered.channels)
    out = Image(rendered.width, rendered.height, rendered.channels);
  apply_exposure(parameters(view), rendered.data.data(), out.data.data(), rendered.pixel_count());
}

void ExposureCompensation::backward_and_step(std::size_t view, const Image& rendered, Image& v_image, float lr) {
  float v_params[kExposureValues];
  apply_exposure_vjp(parameters(view), rendered.data.data(), v_image.data.data(), v_image.data.data(), v_params,
                     rendered.pixel_count());
  const float rates[] = {lr};
  adam_.step(view, v_params, rates);
  // The mean map is the identity: a change common to every view belongs to the model.
  std::vector<float>& p = adam_.parameters();
  const std::size_t n = views();
  for (int k = 0; k < kExposureValues; ++k) {
    double mean = 0;
    for (std::size_t v = 0; v < n; ++v) mean += p[v * kExposureValues + k];
    mean /= double(n);
    for (std::size_t v = 0; v < n; ++v) p[v * kExposureValues + k] -= float(mean);
  }
}

}  // namespace splat
