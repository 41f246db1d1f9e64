#include "splat/train/pose_alignment.hpp"

#include <cmath>
#include <string>
#include <utility>

#include "splat/core/error.hpp"
#include "splat/optim/photometric_loss.hpp"
#include "splat/raster/projection_math.hpp"

namespace splat {

namespace {

constexpr int kRotationValues = 4, kTranslationValues = 3, kValues = kRotationValues + kTranslationValues;
constexpr FlatAdamSettings kPoseAdam{0.9, 0.999, 1e-8};  // PyTorch's defaults

}  // namespace

Camera PoseCorrection::applied_to(const Camera& camera) const {
  Camera corrected = camera;
  apply_pose_correction(Vec4<float>(rotation), Vec3<float>(translation), camera.camera_from_world_rotation,
                        camera.camera_from_world_translation, corrected.camera_from_world_rotation,
                        corrected.camera_from_world_translation);
  return corrected;
}

PoseRefiner::PoseRefiner(std::size_t views, float scene_extent)
    : extent_(scene_extent > 0 ? scene_extent : 1.0f),
      corrections_(views),
      rotation_adams_(views, FlatAdam(kRotationValues, kPoseAdam)),
      translation_adams_(views, FlatAdam(kTranslationValues, kPoseAdam)) {}

void PoseRefiner::step(std::size_t view, const Camera& base, const CameraPoseGradient& gradient,
                       const PoseLearningRates& lr) {
  PoseCorrection& c = corrections_[view];
  Vec4<float> v_q;
  Vec3<float> v_tau;
  apply_pose_correction_vjp(Vec4<float>(c.rotation), base.camera_from_world_rotation,
                            base.camera_from_world_translation, gradient.rotation, gradient.translation, v_q,
                            v_tau);
  const float g_rotation[kRotationValues] = {v_q[0], v_q[1], v_q[2], v_q[3]};
  // τ is stepped in units of the extent: the parameter τ/extent has gradient v_τ·extent.
  const float g_translation[kTranslationValues] = {v_tau[0] * extent_, v_tau[1] * extent_, v_tau[2] * extent_};
  float scaled[kTranslationValues] = {c.translation[0] / extent_, c.translation[1] / extent_,
                                      c.translation[2] / extent_};
  rotation_adams_[view].step({&c.rotation[0], kRotationValues}, g_rotation, lr.rotation);
  translation_adams_[view].step(scaled, g_translation, lr.translation);
  for (int a = 0; a < kTranslationValues; ++a) c.translation[a] = scaled[a] * extent_;
}

std::vector<float> PoseRefiner::parameters() const {
  std::vector<float> out;
  for (const PoseCorrection& c : corrections_) {
    for (int a = 0; a < kRotationValues; ++a) out.push_back(c.rotation[a]);
    for (int a = 0; a < kTranslationValues; ++a) out.push_back(c.translation[a]);
  }
  return out;
}

std::vector<float> PoseRefiner::moments(const std::vector<float>& (FlatAdam::*moment)() const) const {
  std::vector<float> out;
  for (std::size_t v = 0; v < views(); ++v)
    for (const FlatAdam* adam : {&rotation_adams_[v], &translation_adams_[v]}) {
      const std::vector<float>& m = (adam->*moment)();
      out.insert(out.end(), m.begin(), m.end());
    }
  return out;
}

std::vector<float> PoseRefiner::first_moments() const { return moments(&FlatAdam::first_moment); }
std::vector<float> PoseRefiner::second_moments() const { return moments(&FlatAdam::second_moment); }

std::vector<long long> PoseRefiner::steps() const {
  std::vector<long long> out;
  for (const FlatAdam& adam : rotation_adams_) out.push_back(adam.steps());
  return out;
}

void PoseRefiner::restore(const std::vector<float>& parameters, const std::vector<float>& first_moments,
                          const std::vector<float>& second_moments, const std::vector<long long>& steps) {
  const std::size_t n = views() * kValues;
  if (parameters.size() != n || first_moments.size() != n || second_moments.size() != n ||
      steps.size() != views())
    throw ArgumentError("pose corrections: expected " + std::to_string(views()) + " views of " +
                        std::to_string(kValues) + " values");
  for (const std::vector<float>* a : {&parameters, &first_moments, &second_moments})
    for (float x : *a)
      if (!std::isfinite(x)) throw ArgumentError("pose corrections: a value is not finite");
  for (std::size_t v = 0; v < views(); ++v) {
    if (steps[v] < 0) throw ArgumentError("pose corrections: a negative step count");
    const float* p = &parameters[v * kValues];
    for (int a = 0; a < kRotationValues; ++a) corrections_[v].rotation[a] = p[a];
    for (int a = 0; a < kTranslationValues; ++a) corrections_[v].translation[a] = p[kRotationValues + a];
    // Each view's 7 values: the rotation's 4 moments, then the translation's 3.
    const std::pair<FlatAdam*, std::size_t> adams[] = {{&rotation_adams_[v], v * kValues},
                                                       {&translation_adams_[v], v * kValues + kRotationValues}};
    for (const auto& [adam, offset] : adams) {
      for (std::size_t a = 0; a < adam->size(); ++a) {
        adam->first_moment()[a] = first_moments[offset + a];
        adam->second_moment()[a] = second_moments[offset + a];
      }
      adam->set_steps(steps[v]);
    }
  }
}

PoseAlignmentResult align_pose(const GaussianModel& model, const Camera& camera, const Image& photo,
                               const RenderSettings& render, const PoseAlignmentSettings& settings,
                               float scene_extent, const PoseCorrection& start) {
  PoseRefiner refiner(1, scene_extent);
  refiner.set_correction(0, start);
  PoseAlignmentResult result;
  Rasterizer rasterizer;
  RenderResult rendered;
  RasterGradients grads;
  grads.with_camera_pose = true;
  Image v_color;
  SsimScratch scratch;
  for (int step = 0; step <= settings.steps; ++step) {
    const Camera current = refiner.camera(0, camera);
    rasterizer.render(model, current, render, rendered);
    const bool last = step == settings.steps;
    const LossValue loss =
        photometric_loss(rendered.color, photo, settings.ssim_weight, last ? nullptr : &v_color, scratch);
    if (step == 0) result.first_loss = loss.loss;
    // Adam's steps are of the rate's size whatever the gradient, so near the optimum a step
    // can make things worse: the best correction seen is kept, never worse than `start`.
    if (step == 0 || loss.loss < result.loss) {
      result.loss = loss.loss;
      result.correction = refiner.correction(0);
    }
    if (last) break;
    rasterizer.backward(model, current, render, rendered, v_color, grads);
    const double fraction = settings.steps > 1 ? double(step) / double(settings.steps - 1) : 0.0;
    const float decay = float(std::pow(double(settings.lr_final_factor), fraction));
    refiner.step(0, camera, grads.camera_pose, {settings.lr.rotation * decay, settings.lr.translation * decay});
  }
  return result;
}

}  // namespace splat
