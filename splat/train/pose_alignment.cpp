#include "splat/train/pose_alignment.hpp"

#include <cmath>
#include <span>
#include <utility>

#include <glm/gtc/quaternion.hpp>

#include "splat/core/error.hpp"
#include "splat/core/frame_change.hpp"
#include "splat/optim/photometric_loss.hpp"
#include "splat/raster/projection_math.hpp"

namespace splat {

namespace {

constexpr int kRotationValues = 4, kTranslationValues = 3, kValues = kRotationValues + kTranslationValues;
constexpr double kPoseAdamBeta2 = 0.999, kPoseAdamEpsilon = 1e-8;  // PyTorch's defaults

}  // namespace

Camera PoseCorrection::applied_to(const Camera& camera) const {
  Camera corrected = camera;
  apply_pose_correction(Vec4<float>(rotation), Vec3<float>(translation), camera.camera_from_world_rotation,
                        camera.camera_from_world_translation, corrected.camera_from_world_rotation,
                        corrected.camera_from_world_translation, Vec3<float>(0.0f, 0.0f, pivot_depth));
  return corrected;
}

PoseRefiner::PoseRefiner(std::size_t views, float scene_extent, std::vector<float> pivot_depths, double adam_beta1)
    : extent_(scene_extent > 0 ? scene_extent : 1.0f),
      pivot_depths_(pivot_depths.empty() ? std::vector<float>(views, 0.0f) : std::move(pivot_depths)),
      adam_(views, {kRotationValues, kTranslationValues}, {adam_beta1, kPoseAdamBeta2, kPoseAdamEpsilon},
            "pose corrections") {
  if (pivot_depths_.size() != views) throw ArgumentError("pose corrections: a pivot per view is needed");
  for (std::size_t v = 0; v < views; ++v) adam_.parameters(v)[0] = 1.0f;  // the identity quaternion
}

PoseCorrection PoseRefiner::correction(std::size_t view) const {
  const std::span<const float> p = adam_.parameters(view);
  return {{p[0], p[1], p[2], p[3]}, {p[4], p[5], p[6]}, pivot_depths_[view]};
}

void PoseRefiner::set_correction(std::size_t view, const PoseCorrection& correction) {
  const std::span<float> p = adam_.parameters(view);
  for (int a = 0; a < kRotationValues; ++a) p[a] = correction.rotation[a];
  for (int a = 0; a < kTranslationValues; ++a) p[kRotationValues + a] = correction.translation[a];
}

PoseCorrection correction_between(const Camera& from, const Camera& to, float pivot_depth) {
  // to = r·from (rotation) and t_to = r·(t_from − p) + p + τ (apply_pose_correction).
  const glm::dmat3 r = glm::dmat3(to.camera_from_world_rotation) * glm::transpose(glm::dmat3(from.camera_from_world_rotation));
  const glm::dvec3 pivot(0.0, 0.0, pivot_depth);
  const glm::dvec3 tau = glm::dvec3(to.camera_from_world_translation) -
                         r * (glm::dvec3(from.camera_from_world_translation) - pivot) - pivot;
  glm::dquat q = glm::quat_cast(r);
  if (q.w < 0) q = -q;  // the same turn; near the identity this keeps w ≈ +1 as Adam had it
  PoseCorrection correction;
  correction.rotation = glm::vec4(float(q.w), float(q.x), float(q.y), float(q.z));
  correction.translation = glm::vec3(tau);
  correction.pivot_depth = pivot_depth;
  return correction;
}

void PoseRefiner::hold_frame(const std::vector<Camera>& recorded) {
  if (recorded.size() != views()) throw ArgumentError("pose corrections: a recorded camera per view is needed");
  std::vector<Camera> corrected;
  for (std::size_t v = 0; v < views(); ++v) corrected.push_back(camera(v, recorded[v]));
  const FrameChange undo = fit_frame_change(recorded, corrected).inverse();
  for (std::size_t v = 0; v < views(); ++v)
    set_correction(v, correction_between(recorded[v], undo.applied_to(corrected[v]), pivot_depths_[v]));
}

void PoseRefiner::step(std::size_t view, const Camera& base, const CameraPoseGradient& gradient,
                       const PoseLearningRates& lr) {
  Vec4<float> v_q;
  Vec3<float> v_tau;
  apply_pose_correction_vjp(Vec4<float>(correction(view).rotation), base.camera_from_world_rotation,
                            base.camera_from_world_translation, gradient.rotation, gradient.translation, v_q,
                            v_tau, Vec3<float>(0.0f, 0.0f, pivot_depths_[view]));
  const float grad[kValues] = {v_q[0], v_q[1], v_q[2], v_q[3], v_tau[0], v_tau[1], v_tau[2]};
  // Adam's step is the rate's size whatever the gradient's scale: τ's rate, in units of the
  // extent, becomes rate × extent in the scene's units.
  const float rates[] = {lr.rotation, lr.translation * extent_};
  adam_.step(view, grad, rates);
}

PoseAlignmentResult align_pose(const GaussianModel& model, const Camera& camera, const Image& photo,
                               const RenderSettings& render, const PoseAlignmentSettings& settings,
                               float scene_extent, const PoseCorrection& start) {
  PoseRefiner refiner(1, scene_extent, {start.pivot_depth});
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
