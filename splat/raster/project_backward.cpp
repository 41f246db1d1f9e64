#include "splat/raster/project_backward.hpp"

#include <algorithm>
#include <cmath>
#include <tbb/parallel_for.h>

#include "splat/core/spherical_harmonics.hpp"
#include "splat/raster/projection_math.hpp"

namespace splat {

void project_gaussians_backward(const GaussianModel& model, const Camera& camera, int sh_degree,
                                const ProjectedGaussians& projected, const TileBins& bins,
                                const std::vector<Splat2DGrad>& overlap_grads,
                                GaussianModel& grads, std::vector<float>& viewspace_grad_norm,
                                std::vector<float>& blend_weight, CameraPoseGradient* camera_pose) {
  const std::size_t n = model.size();
  grads.sh_degree = model.sh_degree;
  grads.resize(n);
  viewspace_grad_norm.resize(n);
  blend_weight.resize(n);
  const int degree = std::clamp(sh_degree, 0, model.sh_degree);
  const int coeffs_per_gaussian = model.sh_coefficients() * 3;
  const glm::vec3 camera_center = camera.center_in_world();
  const float tan_fov_x = camera.tan_half_fov_x(), tan_fov_y = camera.tan_half_fov_y();
  const Mat3<float>& world_to_camera = camera.camera_from_world_rotation;

  // Fixed blocks, not the scheduler's ranges: the pose gradient is summed per block, then
  // over the blocks in order, so that it does not depend on the thread count.
  constexpr std::size_t kBlock = 512;
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  struct PosePart {
    Mat3<double> rotation{0.0};
    Vec3<double> translation{0.0};
  };
  std::vector<PosePart> pose_parts(camera_pose ? blocks : 0);
  const Vec3<float> translation = camera.camera_from_world_translation;

  tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t block) {
    const tbb::blocked_range<std::size_t> range(block * kBlock, std::min(n, (block + 1) * kBlock));
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      float* v_mean_out = &grads.means[3 * i];
      float* v_log_scale_out = &grads.log_scales[3 * i];
      float* v_quat_out = &grads.quats[4 * i];
      float* v_sh_out = &grads.sh[i * coeffs_per_gaussian];
      std::fill(v_mean_out, v_mean_out + 3, 0.0f);
      std::fill(v_log_scale_out, v_log_scale_out + 3, 0.0f);
      std::fill(v_quat_out, v_quat_out + 4, 0.0f);
      std::fill(v_sh_out, v_sh_out + coeffs_per_gaussian, 0.0f);
      grads.opacity_logits[i] = 0.0f;
      viewspace_grad_norm[i] = 0.0f;
      blend_weight[i] = 0.0f;
      // A Gaussian's records lie in its tiles' lists, far apart: fetch those of a Gaussian a
      // few ahead so the gather below finds them in cache.
      constexpr std::size_t kPrefetchAhead = 4;
      if (i + kPrefetchAhead < range.end())
        for (std::uint32_t j = bins.overlap_start[i + kPrefetchAhead];
             j < bins.overlap_start[i + kPrefetchAhead + 1]; ++j)
          __builtin_prefetch(&overlap_grads[bins.overlap_position[j]]);
      const std::uint32_t first = bins.overlap_start[i], last = bins.overlap_start[i + 1];
      if (first == last) continue;

      // Sum over the Gaussian's tiles, in its rectangle's order.
      Splat2DGrad g{};
      for (std::uint32_t j = first; j < last; ++j) {
        const Splat2DGrad& o = overlap_grads[bins.overlap_position[j]];
        g.mean_x += o.mean_x;
        g.mean_y += o.mean_y;
        g.conic_a += o.conic_a;
        g.conic_b += o.conic_b;
        g.conic_c += o.conic_c;
        g.opacity += o.opacity;
        for (int c = 0; c < 3; ++c) g.color[c] += o.color[c];
        g.blend_weight += o.blend_weight;
      }
      blend_weight[i] = g.blend_weight;
      viewspace_grad_norm[i] = std::hypot(g.mean_x * 0.5f * float(camera.width),
                                          g.mean_y * 0.5f * float(camera.height));

      // Recompute the forward quantities (cheaper than storing them for every Gaussian).
      const glm::vec3 mean = model.mean(i);
      const glm::vec3 mean_camera = camera.camera_from_world(mean);
      const glm::vec3 scale = model.scale(i);
      const glm::vec4 quat = model.quat(i);  // raw: its gradient is the stored parameter's
      const Mat3<float> rotation = quat_to_rotmat(quat);
      const Mat3<float> cov3d = covariance_3d(scale, rotation);
      const Sym2<float> cov2d = covariance_2d(mean_camera, cov3d, world_to_camera, camera.fx,
                                              camera.fy, tan_fov_x, tan_fov_y);
      Vec3<float> conic(0.0f);
      if (!invert_covariance_2d(cov2d, conic)) continue;  // culled in the forward pass too

      // Opacity: o = sigmoid(logit), do/dlogit = o (1 − o).
      const float o = projected.splats[i].opacity;
      grads.opacity_logits[i] = g.opacity * o * (1.0f - o);

      // Colour = max(SH(dir) + 0.5, 0): no gradient in clamped channels.
      const float* coeffs = &model.sh[i * coeffs_per_gaussian];
      const glm::vec3 offset = mean - camera_center;
      const float distance = glm::length(offset);
      const glm::vec3 dir = offset / distance;
      const glm::vec3 raw_color = sh_evaluate(degree, coeffs, dir) + 0.5f;
      glm::vec3 v_color(g.color[0], g.color[1], g.color[2]);
      for (int c = 0; c < 3; ++c)
        if (raw_color[c] < 0.0f) v_color[c] = 0.0f;
      const glm::vec3 v_dir = sh_evaluate_vjp(degree, coeffs, dir, v_color, v_sh_out);
      // dir = offset/|offset|: v_offset = (v_dir − dir (dir·v_dir)) / |offset|.
      const glm::vec3 v_offset = (v_dir - dir * glm::dot(dir, v_dir)) / distance;

      // Conic → Σ' → (camera-space mean, world covariance, and W directly).
      const Sym2<float> v_cov2d = invert_covariance_2d_vjp(conic, Vec3<float>(g.conic_a, g.conic_b, g.conic_c));
      Vec3<float> v_mean_camera;
      Mat3<float> v_cov3d, v_rotation_direct;
      covariance_2d_vjp(mean_camera, cov3d, world_to_camera, camera.fx, camera.fy, tan_fov_x,
                        tan_fov_y, v_cov2d, v_mean_camera, v_cov3d,
                        camera_pose ? &v_rotation_direct : nullptr);
      v_mean_camera += project_to_pixel_vjp(mean_camera, camera.fx, camera.fy,
                                            Vec2<float>(g.mean_x, g.mean_y));
      // mean_camera = W mean + t; offset = mean − C.
      glm::vec3 v_mean = v_offset + glm::transpose(world_to_camera) * v_mean_camera;
      if (camera_pose) {
        Mat3<float> v_rotation = v_rotation_direct;
        Vec3<float> v_translation(0.0f);
        camera_pose_vjp(mean, world_to_camera, translation, v_mean_camera, -v_offset, v_rotation,
                        v_translation);
        PosePart& part = pose_parts[block];
        part.rotation += Mat3<double>(v_rotation);
        part.translation += Vec3<double>(v_translation);
      }

      // Σ = R S Sᵀ Rᵀ → scale (then log-scale: ds/dlog_s = s) and rotation (then quaternion).
      Vec3<float> v_scale;
      Mat3<float> v_rotation;
      covariance_3d_vjp(scale, rotation, v_cov3d, v_scale, v_rotation);
      const Vec4<float> v_quat = quat_to_rotmat_vjp(quat, v_rotation);
      for (int a = 0; a < 3; ++a) {
        v_mean_out[a] = v_mean[a];
        v_log_scale_out[a] = v_scale[a] * scale[a];
      }
      for (int a = 0; a < 4; ++a) v_quat_out[a] = v_quat[a];
    }
  });
  if (camera_pose) {
    PosePart total;
    for (const PosePart& part : pose_parts) {
      total.rotation += part.rotation;
      total.translation += part.translation;
    }
    camera_pose->rotation = glm::mat3(total.rotation);
    camera_pose->translation = glm::vec3(total.translation);
  }
}

}  // namespace splat
