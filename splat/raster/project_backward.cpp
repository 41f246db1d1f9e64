#include "splat/raster/project_backward.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <tbb/parallel_for.h>

#include "splat/core/activations.hpp"
#include "splat/core/spherical_harmonics.hpp"
#include "splat/raster/lane_projection.hpp"
#include "splat/raster/projection_math.hpp"

namespace splat {

namespace {

using namespace lanes;

// The camera's pose gradient, summed in double over a block of Gaussians.
struct PosePart {
  Mat3<double> rotation{0.0};
  Vec3<double> translation{0.0};
};

// What the backward pass needs of the camera, once per view.
struct BackwardView {
  LaneView view;
  glm::vec3 center;
  Mat3<float> rotation;  // W, for the pose gradient
  Vec3<float> translation;
  float width, height;
  int degree, coeffs_per_gaussian;
};

// std::hypot(x, y) of floats, inline: glibc's hypotf is this sum and root in double (the
// same bits over 2·10⁸ random pairs, huge and tiny included), but a call to it per Gaussian
// with its checks for ∞ and NaN cost 1 % of a training iteration. A double holds the squares
// of any two floats without overflow or underflow.
inline float length_2d(float x, float y) { return float(std::sqrt(double(x) * x + double(y) * y)); }

// Summed tile gradients of kLanes Gaussians, one per lane.
struct LaneSplatGrads {
  f32v mean_x{}, mean_y{}, conic_a{}, conic_b{}, conic_c{}, opacity{}, color[3]{};
};

// Chains the summed 2D gradients of Gaussians first .. first + lanes − 1 (bit l of `live`
// for each one that touched a tile) back to their stored parameters, one Gaussian per lane:
// the VJPs of projection_math.hpp, covariance.hpp and spherical_harmonics.hpp chained as
// project_backward.hpp describes, written out for kLanes term for term
// (tests/raster/project_backward_lanes_test.cpp holds each lane to the scalar chain).
// Writes the live lanes' rows (the caller has zeroed the rows of every lane but their SH
// coefficients), and every lane's SH gradient: its rows in `grads`, or its factors in
// `sh_factors` when given (zero in lanes that are not live); returns false if none was live
// after all, having written nothing. Adds the live lanes' pose gradient to `pose`, lane by lane.
bool chain_lanes(const GaussianModel& model, std::size_t first, int lanes, std::uint32_t live,
                 const LaneSplatGrads& g, const BackwardView& cam, GaussianModel& grads,
                 ShGradientFactors* sh_factors, PosePart* pose) {
  const LaneGaussians gaussians(model, first, lanes);
  const LaneShape shape(gaussians, cam.view);
  const f32v xx = shape.xx, xy = shape.xy, yy = shape.yy;
  // invert_covariance_2d; culled in the forward pass where Σ' is singular.
  const f32v det = xx * yy - xy * xy;
  live &= simd::bits(det != 0.0f);
  if (live == 0) return false;
  const f32v inv_det = 1.0f / det;
  const f32v conic_a = yy * inv_det, conic_b = -xy * inv_det, conic_c = xx * inv_det;

  // Opacity: o = sigmoid(logit), do/dlogit = o (1 − o).
  const f32v o = simd::sigmoid(gaussians.opacity_logit);
  const f32v v_logit = g.opacity * o * (1.0f - o);

  // Colour = max(SH(dir) + 0.5, 0): no gradient in clamped channels.
  f32v offset[3], dir[3];
  for (int k = 0; k < 3; ++k) offset[k] = gaussians.mean[k] - cam.center[k];
  const f32v distance = simd::sqrt(offset[0] * offset[0] + offset[1] * offset[1] + offset[2] * offset[2]);
  for (int k = 0; k < 3; ++k) dir[k] = offset[k] / distance;
  f32v basis[16];
  sh_basis_xyz(cam.degree, dir[0], dir[1], dir[2], basis);
  const int count = (cam.degree + 1) * (cam.degree + 1);
  const float* coeffs[kLanes];
  float* v_coeffs[kLanes];
  for (int l = 0; l < kLanes; ++l) {
    const std::size_t i = first + std::size_t(std::min(l, lanes - 1));
    coeffs[l] = &model.sh[i * cam.coeffs_per_gaussian];
    v_coeffs[l] = &grads.sh[i * cam.coeffs_per_gaussian];
  }
  f32v coeff[kMaxShFloats];
  simd::load_columns(coeffs, 3 * count, coeff);
  f32v raw_color[3] = {};
  for (int k = 0; k < count; ++k)
    for (int c = 0; c < 3; ++c) raw_color[c] += basis[k] * coeff[3 * k + c];
  f32v v_color[3];
  for (int c = 0; c < 3; ++c) v_color[c] = raw_color[c] + 0.5f < 0.0f ? f32v{} : g.color[c];
  f32v v_basis[16];
  for (int k = 0; k < count; ++k) {
    v_basis[k] = f32v{};
    for (int c = 0; c < 3; ++c) v_basis[k] += coeff[3 * k + c] * v_color[c];
  }
  // Every lane's SH gradient is written whole here (zero in lanes that are not live), so the
  // largest gradient array is written once rather than cleared and then written.
  i32v live_lanes;
  for (int l = 0; l < kLanes; ++l) live_lanes[l] = -int((live >> l) & 1);
  if (sh_factors) {
    for (int k = 0; k < 3; ++k) {
      const f32v live_dir = live_lanes ? dir[k] : f32v{}, live_color = live_lanes ? v_color[k] : f32v{};
      for (int l = 0; l < lanes; ++l) {
        sh_factors->direction[k][first + std::size_t(l)] = live_dir[l];
        sh_factors->color_grad[k][first + std::size_t(l)] = live_color[l];
      }
    }
  } else {
    store_sh_gradient_rows(cam.degree, basis, v_color, live_lanes, (1u << lanes) - 1, cam.coeffs_per_gaussian,
                           v_coeffs);
  }
  f32v v_dir[3] = {};
  sh_basis_vjp_xyz(cam.degree, dir[0], dir[1], dir[2], v_basis, v_dir[0], v_dir[1], v_dir[2]);
  // dir = offset/|offset|: v_offset = (v_dir − dir (dir·v_dir)) / |offset|.
  const f32v dir_dot = dir[0] * v_dir[0] + dir[1] * v_dir[1] + dir[2] * v_dir[2];
  f32v v_offset[3];
  for (int k = 0; k < 3; ++k) v_offset[k] = (v_dir[k] - dir[k] * dir_dot) / distance;

  // invert_covariance_2d_vjp: conic → Σ'.
  const f32v h00 = g.conic_a, h01 = 0.5f * g.conic_b, h11 = g.conic_c;
  const f32v qh00 = conic_a * h00 + conic_b * h01, qh01 = conic_a * h01 + conic_b * h11;
  const f32v qh10 = conic_b * h00 + conic_c * h01, qh11 = conic_b * h01 + conic_c * h11;
  const f32v v_xx = -(qh00 * conic_a + qh01 * conic_b);
  const f32v v_xy = -2.0f * (qh00 * conic_b + qh01 * conic_c);
  const f32v v_yy = -(qh10 * conic_b + qh11 * conic_c);

  // covariance_2d_vjp: with T = J W, v_Σ = Tᵀ G T, v_T = (G + Gᵀ) T Σ, v_J = v_T Wᵀ.
  const f32v zero{};
  const LaneMat3 g2{{{v_xx, v_xy, zero}, {zero, v_yy, zero}, {zero, zero, zero}}};
  const LaneMat3 g2_sym{{{v_xx + v_xx, v_xy, zero}, {v_xy, v_yy + v_yy, zero}, {zero, zero, zero}}};
  const LaneMat3& t = shape.jacobian_view;
  const LaneMat3 v_cov3d = multiply(multiply(transpose(t), g2), t);
  const LaneMat3 v_t = multiply(multiply(g2_sym, t), shape.cov3d);
  const LaneMat3 v_j = multiply(v_t, transpose(cam.view.rotation));
  const f32v z = shape.mean_camera[2], z2 = z * z, z3 = z2 * z;
  const float fx = cam.view.fx, fy = cam.view.fy;
  const f32v v_x = -fx / z2 * v_j.m[0][2];
  const f32v v_y = -fy / z2 * v_j.m[1][2];
  f32v v_z = -fx / z2 * v_j.m[0][0] + 2.0f * fx * shape.clamped_x / z3 * v_j.m[0][2] -
             fy / z2 * v_j.m[1][1] + 2.0f * fy * shape.clamped_y / z3 * v_j.m[1][2];
  const f32v ratio_x = shape.mean_camera[0] / z, ratio_y = shape.mean_camera[1] / z;
  const i32v clamped_x = (ratio_x < -cam.view.limit_x) | (ratio_x > cam.view.limit_x);
  const i32v clamped_y = (ratio_y < -cam.view.limit_y) | (ratio_y > cam.view.limit_y);
  v_z += clamped_x ? (shape.clamped_x / z) * v_x : zero;
  v_z += clamped_y ? (shape.clamped_y / z) * v_y : zero;
  f32v v_mean_camera[3] = {clamped_x ? zero : v_x, clamped_y ? zero : v_y, v_z};
  // project_to_pixel_vjp.
  const f32v inv_z = 1.0f / z;
  v_mean_camera[0] += fx * inv_z * g.mean_x;
  v_mean_camera[1] += fy * inv_z * g.mean_y;
  v_mean_camera[2] += -(fx * shape.mean_camera[0] * g.mean_x + fy * shape.mean_camera[1] * g.mean_y) * inv_z * inv_z;
  // mean_camera = W mean + t; offset = mean − C.
  f32v v_mean[3];
  for (int a = 0; a < 3; ++a)
    v_mean[a] = v_offset[a] + (cam.view.rotation.m[0][a] * v_mean_camera[0] + cam.view.rotation.m[1][a] * v_mean_camera[1] +
                               cam.view.rotation.m[2][a] * v_mean_camera[2]);

  if (pose) {
    // W's direct use in T = J W, then camera_pose_vjp, one Gaussian (lane) at a time.
    const LaneMat3 v_rotation_direct = multiply(transpose(shape.jacobian), v_t);
    for (std::uint32_t todo = live; todo != 0; todo &= todo - 1) {
      const int l = __builtin_ctz(todo);
      Mat3<float> v_rotation;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) at(v_rotation, r, c) = v_rotation_direct.m[r][c][l];
      Vec3<float> v_translation(0.0f);
      const Vec3<float> mean(gaussians.mean[0][l], gaussians.mean[1][l], gaussians.mean[2][l]);
      const Vec3<float> v_mc(v_mean_camera[0][l], v_mean_camera[1][l], v_mean_camera[2][l]);
      const Vec3<float> v_center(-v_offset[0][l], -v_offset[1][l], -v_offset[2][l]);
      camera_pose_vjp(mean, cam.rotation, cam.translation, v_mc, v_center, v_rotation, v_translation);
      pose->rotation += Mat3<double>(v_rotation);
      pose->translation += Vec3<double>(v_translation);
    }
  }

  // covariance_3d_vjp: Σ = M Mᵀ with M = R S; v_M = (v_Σ + v_Σᵀ) M, v_R[:, j] = s_j v_M[:, j],
  // v_s_j = R[:, j] · v_M[:, j].
  LaneMat3 m = shape.rotation;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m.m[i][j] = m.m[i][j] * shape.scale[j];
  LaneMat3 v_cov_sym;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) v_cov_sym.m[i][j] = v_cov3d.m[i][j] + v_cov3d.m[j][i];
  const LaneMat3 v_m = multiply(v_cov_sym, m);
  LaneMat3 v_r;
  f32v v_scale[3];
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) v_r.m[i][j] = v_m.m[i][j] * shape.scale[j];
    v_scale[j] = shape.rotation.m[0][j] * v_m.m[0][j] + shape.rotation.m[1][j] * v_m.m[1][j] +
                 shape.rotation.m[2][j] * v_m.m[2][j];
  }

  // quat_to_rotmat_vjp: v_n from v_R, then through n = q/|q|.
  const f32v* q = gaussians.quat;
  const f32v norm = simd::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  const f32v w = q[0] / norm, x = q[1] / norm, y = q[2] / norm, zq = q[3] / norm;
  auto gr = [&](int row, int col) { return v_r.m[row][col]; };
  f32v v_n[4];
  v_n[0] = 2.0f * (-zq * gr(0, 1) + y * gr(0, 2) + zq * gr(1, 0) - x * gr(1, 2) - y * gr(2, 0) + x * gr(2, 1));
  v_n[1] = 2.0f * (y * gr(0, 1) + zq * gr(0, 2) + y * gr(1, 0) - 2.0f * x * gr(1, 1) - w * gr(1, 2) +
                   zq * gr(2, 0) + w * gr(2, 1) - 2.0f * x * gr(2, 2));
  v_n[2] = 2.0f * (-2.0f * y * gr(0, 0) + x * gr(0, 1) + w * gr(0, 2) + x * gr(1, 0) + zq * gr(1, 2) -
                   w * gr(2, 0) + zq * gr(2, 1) - 2.0f * y * gr(2, 2));
  v_n[3] = 2.0f * (-2.0f * zq * gr(0, 0) - w * gr(0, 1) + x * gr(0, 2) + w * gr(1, 0) -
                   2.0f * zq * gr(1, 1) + y * gr(1, 2) + x * gr(2, 0) + y * gr(2, 1));
  const f32v n[4] = {w, x, y, zq};
  const f32v n_dot = n[0] * v_n[0] + n[1] * v_n[1] + n[2] * v_n[2] + n[3] * v_n[3];

  for (std::uint32_t todo = live; todo != 0; todo &= todo - 1) {
    const int l = __builtin_ctz(todo);
    const std::size_t i = first + std::size_t(l);
    grads.opacity_logits[i] = v_logit[l];
    for (int a = 0; a < 3; ++a) {
      grads.means[3 * i + a] = v_mean[a][l];
      grads.log_scales[3 * i + a] = v_scale[a][l] * shape.scale[a][l];
    }
    for (int a = 0; a < 4; ++a) grads.quats[4 * i + a] = ((v_n[a] - n[a] * n_dot) / norm)[l];
  }
  return true;
}

}  // namespace

void project_gaussians_backward(const GaussianModel& model, const Camera& camera, int sh_degree,
                                const TileBins& bins,
                                const OverlapGradients& overlap,
                                GaussianModel& grads, std::vector<float>& viewspace_grad_norm,
                                std::vector<float>& blend_weight, CameraPoseGradient* camera_pose,
                                ShGradientFactors* sh_factors) {
  const std::size_t n = model.size();
  grads.sh_degree = model.sh_degree;
  grads.resize(n);
  if (sh_factors) sh_factors->resize(n);
  viewspace_grad_norm.resize(n);
  blend_weight.resize(n);
  const int coeffs_per_gaussian = model.sh_coefficients() * 3;
  const BackwardView cam{LaneView(camera),
                         camera.center_in_world(),
                         camera.camera_from_world_rotation,
                         camera.camera_from_world_translation,
                         float(camera.width),
                         float(camera.height),
                         std::clamp(sh_degree, 0, model.sh_degree),
                         coeffs_per_gaussian};
  if (sh_factors) sh_factors->degree = cam.degree;

  // Fixed blocks, not the scheduler's ranges: the pose gradient is summed per block, then
  // over the blocks in order, so that it does not depend on the thread count.
  constexpr std::size_t kBlock = 512;
  static_assert(kBlock % kLanes == 0, "blocks hold whole groups of lanes");
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<PosePart> pose_parts(camera_pose ? blocks : 0);

  tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t block) {
    const std::size_t begin = block * kBlock, end = std::min(n, (block + 1) * kBlock);
    // Rows without a gradient are zero (the SH rows are cleared as chain_lanes passes them).
    auto clear = [&](std::vector<float>& array, std::size_t width) {
      std::memset(&array[begin * width], 0, (end - begin) * width * sizeof(float));
    };
    clear(grads.means, 3);
    clear(grads.log_scales, 3);
    clear(grads.quats, 4);
    clear(grads.opacity_logits, 1);
    for (std::size_t first = begin; first < end; first += kLanes) {
      const int lanes = int(std::min<std::size_t>(kLanes, end - first));
      LaneSplatGrads lane_grads;
      std::uint32_t live = 0;
      for (int l = 0; l < lanes; ++l) {
        const std::size_t i = first + std::size_t(l);
        const std::uint32_t first_overlap = bins.overlap_start[i], last_overlap = bins.overlap_start[i + 1];
        // Sum over the Gaussian's tiles, in its rectangle's order.
        Splat2DGrad g{};
        for (std::uint32_t j = first_overlap; j < last_overlap; ++j) {
          if (!overlap.written(j)) continue;  // blended nowhere in that tile: zero
          const Splat2DGrad& o = overlap.records[j].grad;
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
        viewspace_grad_norm[i] = length_2d(g.mean_x * 0.5f * cam.width, g.mean_y * 0.5f * cam.height);
        if (first_overlap == last_overlap) continue;
        live |= 1u << l;
        lane_grads.mean_x[l] = g.mean_x;
        lane_grads.mean_y[l] = g.mean_y;
        lane_grads.conic_a[l] = g.conic_a;
        lane_grads.conic_b[l] = g.conic_b;
        lane_grads.conic_c[l] = g.conic_c;
        lane_grads.opacity[l] = g.opacity;
        for (int c = 0; c < 3; ++c) lane_grads.color[c][l] = g.color[c];
      }
      if (live == 0 || !chain_lanes(model, first, lanes, live, lane_grads, cam, grads, sh_factors,
                                    camera_pose ? &pose_parts[block] : nullptr)) {
        if (sh_factors) sh_factors->clear(first, std::size_t(lanes));
        else std::memset(&grads.sh[first * coeffs_per_gaussian], 0, std::size_t(lanes) * coeffs_per_gaussian * sizeof(float));
      }
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
