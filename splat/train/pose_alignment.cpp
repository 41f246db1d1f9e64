#include "splat/train/pose_alignment.hpp"

#include "splat/optim/flat_adam.hpp"
#include "splat/optim/photometric_loss.hpp"
#include "splat/raster/projection_math.hpp"

namespace splat {

Camera PoseCorrection::applied_to(const Camera& camera) const {
  Camera corrected = camera;
  apply_pose_correction(Vec4<float>(rotation), Vec3<float>(translation), camera.camera_from_world_rotation,
                        camera.camera_from_world_translation, corrected.camera_from_world_rotation,
                        corrected.camera_from_world_translation);
  return corrected;
}

PoseAlignmentResult align_pose(const GaussianModel& model, const Camera& camera, const Image& photo,
                               const RenderSettings& render, const PoseAlignmentSettings& settings,
                               float scene_extent, const PoseCorrection& start) {
  PoseAlignmentResult result;
  result.correction = start;
  PoseCorrection& c = result.correction;
  FlatAdam rotation_adam(4), translation_adam(3);
  Rasterizer rasterizer;
  RenderResult rendered;
  RasterGradients grads;
  grads.with_camera_pose = true;
  Image v_color;
  SsimScratch scratch;
  // Steps on τ / extent, so that one learning rate suits scenes of any size.
  const float extent = scene_extent > 0 ? scene_extent : 1.0f;
  for (int step = 0; step <= settings.steps; ++step) {
    const Camera current = c.applied_to(camera);
    rasterizer.render(model, current, render, rendered);
    const bool last = step == settings.steps;
    const LossValue loss =
        photometric_loss(rendered.color, photo, settings.ssim_weight, last ? nullptr : &v_color, scratch);
    if (step == 0) result.first_loss = loss.loss;
    result.last_loss = loss.loss;
    if (last) break;
    rasterizer.backward(model, current, render, rendered, v_color, grads);
    Vec4<float> v_q;
    Vec3<float> v_tau;
    apply_pose_correction_vjp(Vec4<float>(c.rotation), camera.camera_from_world_rotation,
                              camera.camera_from_world_translation, grads.camera_pose.rotation,
                              grads.camera_pose.translation, v_q, v_tau);
    const float g_rotation[4] = {v_q[0], v_q[1], v_q[2], v_q[3]};
    const float g_translation[3] = {v_tau[0] * extent, v_tau[1] * extent, v_tau[2] * extent};
    float scaled_translation[3] = {c.translation[0] / extent, c.translation[1] / extent, c.translation[2] / extent};
    rotation_adam.step({&c.rotation[0], 4}, g_rotation, settings.rotation_lr);
    translation_adam.step(scaled_translation, g_translation, settings.translation_lr);
    for (int a = 0; a < 3; ++a) c.translation[a] = scaled_translation[a] * extent;
  }
  return result;
}

}  // namespace splat
