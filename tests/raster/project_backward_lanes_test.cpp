// project_gaussians_backward chains kLanes Gaussians at a time (lane_projection.hpp); every
// lane must give what the scalar VJPs of projection_math.hpp, covariance.hpp and
// spherical_harmonics.hpp give one Gaussian at a time (those are checked in double and
// against finite differences by projection_vjp_test.cpp). The reference below chains them as
// the backward pass did before it was vectorised. Tile records are random, so every term of
// the chain is exercised, clamped colour channels and clamped Jacobians included.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "splat/core/spherical_harmonics.hpp"
#include "splat/raster/bin_sort.hpp"
#include "splat/raster/project.hpp"
#include "splat/raster/project_backward.hpp"
#include "splat/raster/projection_math.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

// One Gaussian's parameter gradients and its share of the pose gradient.
template <class T>
struct GaussianGrads {
  T means[3], log_scales[3], quats[4], opacity_logit;
  std::vector<T> sh;
  Mat3<T> pose_rotation{T(0)};
  Vec3<T> pose_translation{T(0)};
};

// Gaussian i's gradients from its summed 2D gradient `g`, with the scalar functions in T (the
// model's float parameters converted). Returns false where the forward pass culled it.
template <class T>
bool chain_one(const GaussianModel& model, const Camera& camera, int degree, std::size_t i,
               const Splat2DGrad& g, GaussianGrads<T>& out) {
  const Mat3<T> world_to_camera(camera.camera_from_world_rotation);
  const Vec3<T> translation(camera.camera_from_world_translation);
  const T fx = camera.fx, fy = camera.fy, tan_fov_x = camera.tan_half_fov_x(), tan_fov_y = camera.tan_half_fov_y();
  const Vec3<T> mean(model.mean(i));
  const Vec3<T> mean_camera = world_to_camera * mean + translation;
  const Vec3<T> scale(std::exp(T(model.log_scales[3 * i])), std::exp(T(model.log_scales[3 * i + 1])),
                      std::exp(T(model.log_scales[3 * i + 2])));
  const Vec4<T> quat(model.quat(i));
  const Mat3<T> rotation = quat_to_rotmat(quat);
  const Mat3<T> cov3d = covariance_3d(scale, rotation);
  const Sym2<T> cov2d = covariance_2d(mean_camera, cov3d, world_to_camera, fx, fy, tan_fov_x, tan_fov_y);
  Vec3<T> conic(T(0));
  if (!invert_covariance_2d(cov2d, conic)) return false;
  const T o = T(1) / (T(1) + std::exp(-T(model.opacity_logits[i])));
  out.opacity_logit = T(g.opacity) * o * (T(1) - o);

  const int coeffs_per_gaussian = model.sh_coefficients() * 3;
  std::vector<T> coeffs(&model.sh[i * coeffs_per_gaussian], &model.sh[(i + 1) * coeffs_per_gaussian]);
  out.sh.assign(coeffs_per_gaussian, T(0));
  const Vec3<T> offset = mean - Vec3<T>(camera.center_in_world());
  const T distance = glm::length(offset);
  const Vec3<T> dir = offset / distance;
  const Vec3<T> raw_color = sh_evaluate(degree, coeffs.data(), dir) + T(0.5);
  Vec3<T> v_color(g.color[0], g.color[1], g.color[2]);
  for (int c = 0; c < 3; ++c)
    if (raw_color[c] < T(0)) v_color[c] = T(0);
  const Vec3<T> v_dir = sh_evaluate_vjp(degree, coeffs.data(), dir, v_color, out.sh.data());
  const Vec3<T> v_offset = (v_dir - dir * glm::dot(dir, v_dir)) / distance;

  const Sym2<T> v_cov2d = invert_covariance_2d_vjp(conic, Vec3<T>(g.conic_a, g.conic_b, g.conic_c));
  Vec3<T> v_mean_camera;
  Mat3<T> v_cov3d;
  covariance_2d_vjp(mean_camera, cov3d, world_to_camera, fx, fy, tan_fov_x, tan_fov_y, v_cov2d, v_mean_camera,
                    v_cov3d, &out.pose_rotation);
  v_mean_camera += project_to_pixel_vjp(mean_camera, fx, fy, Vec2<T>(g.mean_x, g.mean_y));
  const Vec3<T> v_mean = v_offset + glm::transpose(world_to_camera) * v_mean_camera;
  camera_pose_vjp(mean, world_to_camera, translation, v_mean_camera, -v_offset, out.pose_rotation,
                  out.pose_translation);

  Vec3<T> v_scale;
  Mat3<T> v_rot;
  covariance_3d_vjp(scale, rotation, v_cov3d, v_scale, v_rot);
  const Vec4<T> v_quat = quat_to_rotmat_vjp(quat, v_rot);
  for (int a = 0; a < 3; ++a) {
    out.means[a] = v_mean[a];
    out.log_scales[a] = v_scale[a] * scale[a];
  }
  for (int a = 0; a < 4; ++a) out.quats[a] = v_quat[a];
  return true;
}

// The worst error of the lanes' and of the scalar float chain's results against the double
// chain, per group, each relative to the group's largest gradient.
struct GroupErrors {
  double scale = 0, lanes = 0, scalar = 0;
  void add(double exact, float lane, float scalar_float) {
    scale = std::max(scale, std::abs(exact));
    lanes = std::max(lanes, std::abs(double(lane) - exact));
    scalar = std::max(scalar, std::abs(double(scalar_float) - exact));
  }
  double lanes_relative() const { return scale == 0 ? lanes : lanes / scale; }
  double scalar_relative() const { return scale == 0 ? scalar : scalar / scale; }
};

void expect_lanes_match_scalar(const GaussianModel& model, const Camera& camera, int degree) {
  ProjectedGaussians projected;
  project_gaussians(model, camera, degree, projected);
  TileBins bins;
  bin_and_sort(projected, TileGrid::for_image(camera.width, camera.height), true, bins);
  std::mt19937 rng(7);
  std::normal_distribution<float> normal(0.0f, 1.0f);
  // Random records, a quarter of them not written (they must count as zero).
  OverlapGradients overlap;
  overlap.start_frame(bins.gaussian_ids.size());
  overlap.start_frame(bins.gaussian_ids.size());  // the second frame: stamps 1 are stale
  std::bernoulli_distribution written(0.75);
  for (OverlapGradients::Record& record : overlap.records)
    record = {{normal(rng), normal(rng), normal(rng), normal(rng), normal(rng), normal(rng),
               {normal(rng), normal(rng), normal(rng)}, std::abs(normal(rng))},
              written(rng) ? overlap.frame : overlap.frame - 1};

  // Filled with garbage first: the backward pass must overwrite every entry.
  GaussianModel lanes;
  lanes.sh_degree = model.sh_degree;
  lanes.resize(model.size());
  for (std::vector<float>* array : {&lanes.means, &lanes.log_scales, &lanes.quats, &lanes.opacity_logits, &lanes.sh})
    std::fill(array->begin(), array->end(), 7.0f);
  std::vector<float> norm, weight;
  CameraPoseGradient pose;
  project_gaussians_backward(model, camera, degree, bins, overlap, lanes, norm, weight, &pose);

  const int coeffs_per_gaussian = model.sh_coefficients() * 3;
  {
    // The SH gradient as its factors: the same rows to the bit once formed, every other
    // group the same, and the model's SH rows not written.
    GaussianModel factored;
    factored.sh_degree = model.sh_degree;
    factored.resize(model.size());
    std::fill(factored.sh.begin(), factored.sh.end(), 7.0f);
    ShGradientFactors factors;
    factors.resize(model.size());
    for (int k = 0; k < 3; ++k) std::fill(factors.color_grad[k].begin(), factors.color_grad[k].end(), 7.0f);
    std::vector<float> factored_norm, factored_weight;
    CameraPoseGradient factored_pose;
    project_gaussians_backward(model, camera, degree, bins, overlap, factored, factored_norm, factored_weight,
                               &factored_pose, &factors);
    EXPECT_EQ(factors.degree, degree);
    EXPECT_EQ(factored.means, lanes.means);
    EXPECT_EQ(factored.log_scales, lanes.log_scales);
    EXPECT_EQ(factored.quats, lanes.quats);
    EXPECT_EQ(factored.opacity_logits, lanes.opacity_logits);
    EXPECT_EQ(factored_norm, norm);
    EXPECT_EQ(factored_weight, weight);
    EXPECT_EQ(factored_pose.rotation, pose.rotation);
    EXPECT_EQ(factored_pose.translation, pose.translation);
    EXPECT_TRUE(std::all_of(factored.sh.begin(), factored.sh.end(), [](float x) { return x == 7.0f; }));
    std::vector<float> rows(simd::kLanes * std::size_t(coeffs_per_gaussian), 7.0f);
    int mismatches = 0;
    for (std::size_t first = 0; first < model.size(); first += simd::kLanes) {
      const int count = int(std::min<std::size_t>(simd::kLanes, model.size() - first));
      factors.expand(first, count, coeffs_per_gaussian, rows.data());
      for (std::size_t e = 0; e < std::size_t(count * coeffs_per_gaussian); ++e) {
        const float dense = lanes.sh[first * coeffs_per_gaussian + e];
        // Equal as floats: bit for bit but for the sign of a zero (a Gaussian without a
        // gradient), which Adam's step does not see.
        mismatches += !(rows[e] == dense);
      }
    }
    EXPECT_EQ(mismatches, 0);
  }
  enum { kMeans, kLogScales, kQuats, kOpacity, kSh, kPose, kGroups };
  const char* names[kGroups] = {"means", "log-scales", "quats", "opacity", "sh", "pose"};
  GroupErrors errors[kGroups];
  Mat3<double> pose_rotation(0.0);
  Vec3<double> pose_translation(0.0);
  Mat3<float> scalar_pose_rotation(0.0f);
  Vec3<float> scalar_pose_translation(0.0f);
  int chained = 0;
  for (std::size_t i = 0; i < model.size(); ++i) {
    Splat2DGrad g{};
    for (std::uint32_t j = bins.overlap_start[i]; j < bins.overlap_start[i + 1]; ++j) {
      if (!overlap.written(j)) continue;
      const Splat2DGrad& o = overlap.records[j].grad;
      g.mean_x += o.mean_x, g.mean_y += o.mean_y, g.conic_a += o.conic_a, g.conic_b += o.conic_b;
      g.conic_c += o.conic_c, g.opacity += o.opacity, g.blend_weight += o.blend_weight;
      for (int c = 0; c < 3; ++c) g.color[c] += o.color[c];
    }
    // The summed records are the same to the bit: only the chain differs.
    EXPECT_EQ(weight[i], g.blend_weight);
    EXPECT_EQ(norm[i], std::hypot(g.mean_x * 0.5f * float(camera.width), g.mean_y * 0.5f * float(camera.height)));
    GaussianGrads<double> exact;
    GaussianGrads<float> scalar;
    const bool touched = bins.overlap_start[i] != bins.overlap_start[i + 1];
    if (!touched || !chain_one(model, camera, degree, i, g, exact)) {
      // Untouched or culled: zero gradients.
      EXPECT_EQ(lanes.opacity_logits[i], 0.0f);
      for (int a = 0; a < 3; ++a) EXPECT_EQ(lanes.means[3 * i + a], 0.0f);
      for (int a = 0; a < 3; ++a) EXPECT_EQ(lanes.log_scales[3 * i + a], 0.0f);
      for (int a = 0; a < 4; ++a) EXPECT_EQ(lanes.quats[4 * i + a], 0.0f);
      for (int k = 0; k < coeffs_per_gaussian; ++k) ASSERT_EQ(lanes.sh[i * coeffs_per_gaussian + k], 0.0f) << i;
      continue;
    }
    ASSERT_TRUE(chain_one(model, camera, degree, i, g, scalar));
    ++chained;
    for (int a = 0; a < 3; ++a) errors[kMeans].add(exact.means[a], lanes.means[3 * i + a], scalar.means[a]);
    for (int a = 0; a < 3; ++a)
      errors[kLogScales].add(exact.log_scales[a], lanes.log_scales[3 * i + a], scalar.log_scales[a]);
    for (int a = 0; a < 4; ++a) errors[kQuats].add(exact.quats[a], lanes.quats[4 * i + a], scalar.quats[a]);
    errors[kOpacity].add(exact.opacity_logit, lanes.opacity_logits[i], scalar.opacity_logit);
    for (int k = 0; k < coeffs_per_gaussian; ++k)
      errors[kSh].add(exact.sh[k], lanes.sh[i * coeffs_per_gaussian + k], scalar.sh[k]);
    pose_rotation += exact.pose_rotation;
    pose_translation += exact.pose_translation;
    scalar_pose_rotation += scalar.pose_rotation;
    scalar_pose_translation += scalar.pose_translation;
  }
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      errors[kPose].add(at(pose_rotation, r, c), at(Mat3<float>(pose.rotation), r, c), at(scalar_pose_rotation, r, c));
  for (int k = 0; k < 3; ++k) errors[kPose].add(pose_translation[k], pose.translation[k], scalar_pose_translation[k]);

  EXPECT_GT(chained, 100);
  std::printf("%d of %zu Gaussians chained; worst error against double, relative to the group's largest "
              "gradient (lanes / scalar float):",
              chained, model.size());
  for (int k = 0; k < kGroups; ++k) {
    std::printf(" %s %.2g / %.2g;", names[k], errors[k].lanes_relative(), errors[k].scalar_relative());
    // As accurate as the scalar float chain (its roundings, amplified by ill-conditioned
    // footprints, set the scale), up to a factor for the different order of the sums.
    EXPECT_LE(errors[k].lanes_relative(), std::max(4 * errors[k].scalar_relative(), 1e-6)) << names[k];
  }
  std::printf("\n");
}

TEST(ProjectBackwardLanes, EveryLaneChainsAsTheScalarFunctions) {
  // Some Gaussians off to the side (clamped Jacobian), some very flat, a count that is not a
  // multiple of the lanes or of the pose gradient's blocks.
  GaussianModel model = test::random_model(3001, 3, 11, 2.5f, 0.001f, 0.8f);
  for (std::size_t i = 0; i < model.size(); i += 7) model.log_scales[3 * i + 1] = std::log(1e-4f);
  const Camera camera = test::looking_at_origin(173, 111, 3.0f, 0.9f);
  for (int degree : {0, 1, 3}) expect_lanes_match_scalar(model, camera, degree);
}

TEST(ProjectBackwardLanes, ConformanceModelChainsAsTheScalarFunctions) {
  const test::ConformanceScene scene = test::load_conformance(400);
  ASSERT_FALSE(scene.frames.empty());
  expect_lanes_match_scalar(scene.model, scene.frames[0].camera, 3);
}

}  // namespace
}  // namespace splat
