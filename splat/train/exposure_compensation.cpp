#include "splat/train/exposure_compensation.hpp"

#include <cmath>
#include <string>

#include "splat/core/error.hpp"

namespace splat {

ExposureCompensation::ExposureCompensation(std::size_t views)
    : parameters_(views * kExposureValues, 0.0f), adams_(views, FlatAdam(kExposureValues, {0.9, 0.999, 1e-8})) {}

void ExposureCompensation::apply(std::size_t view, const Image& rendered, Image& out) const {
  if (out.width != rendered.width || out.height != rendered.height || out.channels != rendered.channels)
    out = Image(rendered.width, rendered.height, rendered.channels);
  apply_exposure(parameters(view), rendered.data.data(), out.data.data(), rendered.pixel_count());
}

void ExposureCompensation::backward_and_step(std::size_t view, const Image& rendered, Image& v_image, float lr) {
  float v_params[kExposureValues];
  apply_exposure_vjp(parameters(view), rendered.data.data(), v_image.data.data(), v_image.data.data(), v_params,
                     rendered.pixel_count());
  float* p = &parameters_[view * kExposureValues];
  adams_[view].step({p, kExposureValues}, v_params, lr);
  // The mean map is the identity: a change common to every view belongs to the model.
  const std::size_t n = views();
  for (int k = 0; k < kExposureValues; ++k) {
    double mean = 0;
    for (std::size_t v = 0; v < n; ++v) mean += parameters_[v * kExposureValues + k];
    mean /= double(n);
    for (std::size_t v = 0; v < n; ++v) parameters_[v * kExposureValues + k] -= float(mean);
  }
}

std::vector<float> ExposureCompensation::first_moments() const {
  std::vector<float> out;
  for (const FlatAdam& adam : adams_) out.insert(out.end(), adam.first_moment().begin(), adam.first_moment().end());
  return out;
}

std::vector<float> ExposureCompensation::second_moments() const {
  std::vector<float> out;
  for (const FlatAdam& adam : adams_) out.insert(out.end(), adam.second_moment().begin(), adam.second_moment().end());
  return out;
}

std::vector<long long> ExposureCompensation::steps() const {
  std::vector<long long> out;
  for (const FlatAdam& adam : adams_) out.push_back(adam.steps());
  return out;
}

void ExposureCompensation::restore(const std::vector<float>& parameters, const std::vector<float>& first_moments,
                                   const std::vector<float>& second_moments, const std::vector<long long>& steps) {
  const std::size_t n = views() * kExposureValues;
  if (parameters.size() != n || first_moments.size() != n || second_moments.size() != n || steps.size() != views())
    throw ArgumentError("exposure maps: expected " + std::to_string(views()) + " views of " +
                        std::to_string(kExposureValues) + " values");
  for (const std::vector<float>* a : {&parameters, &first_moments, &second_moments})
    for (float x : *a)
      if (!std::isfinite(x)) throw ArgumentError("exposure maps: a value is not finite");
  parameters_ = parameters;
  for (std::size_t v = 0; v < views(); ++v) {
    if (steps[v] < 0) throw ArgumentError("exposure maps: a negative step count");
    for (int k = 0; k < kExposureValues; ++k) {
      adams_[v].first_moment()[k] = first_moments[v * kExposureValues + k];
      adams_[v].second_moment()[k] = second_moments[v * kExposureValues + k];
    }
    adams_[v].set_steps(steps[v]);
  }
}

}  // namespace splat
