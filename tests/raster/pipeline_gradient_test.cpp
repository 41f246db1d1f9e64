// The whole rasterizer's gradient (tiled, float, SIMD) against central finite differences of
// a double-precision per-pixel reference render, for L = Σ W·I with random weights W.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "tests/gradient_check.hpp"
#include "splat/composite/composite.hpp"
#include "splat/core/spherical_harmonics.hpp"
#include "splat/raster/projection_math.hpp"
#include "splat/raster/rasterizer.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

// The model's arrays, concatenated in this order, are the parameter vector.
std::vector<double> flatten(const GaussianModel& m) {
  std::vector<double> x;
  for (const auto* a : {&m.means, &m.log_scales, &m.quats, &m.opacity_logits, &m.sh})
    x.insert(x.end(), a->begin(), a->end());
  return x;
}

struct DoubleModel {
  std::size_t n;
  int degree;
  const double *means, *log_scales, *quats, *logits, *sh;
  DoubleModel(const std::vector<double>& x, std::size_t n_, int degree_) : n(n_), degree(degree_) {
    means = x.data();
    log_scales = means + 3 * n;
    quats = log_scales + 3 * n;
    logits = quats + 4 * n;
    sh = logits + n;
  }
};

// Σ W·I of the image rendered in double, pixel by pixel, with the rasterizer's rules (near
// plane, Jacobian clamp, dilation, the reference tile rectangles, 1/255 skip, 0.99 clamp,
// early stop).
// `pose`, if given, replaces the camera's rotation and translation (in double).
struct DoublePose {
  Mat3<double> rotation;
  Vec3<double> translation;
};

double reference_loss(const std::vector<double>& x, std::size_t n, int degree,
                      const Camera& camera, const std::vector<double>& weights,
                      const float background[3], const DoublePose* pose = nullptr) {
  const DoubleModel m(x, n, degree);
  Mat3<double> rotation_cw;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) rotation_cw[c][r] = camera.camera_from_world_rotation[c][r];
  Vec3<double> t(camera.camera_from_world_translation);
  if (pose) {
    rotation_cw = pose->rotation;
    t = pose->translation;
  }
  const Vec3<double> center = -(glm::transpose(rotation_cw) * t);
  const TileGrid grid = TileGrid::for_image(camera.width, camera.height);
  const int k_count = (degree + 1) * (degree + 1);

  struct Splat {
    double depth, mx, my, a, b, c, opacity, color[3];
    TileRect rect;
  };
  std::vector<Splat> splats;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3<double> mean(m.means[3 * i], m.means[3 * i + 1], m.means[3 * i + 2]);
    const Vec3<double> mc = rotation_cw * mean + t;
    if (!(mc.z > kNearPlane)) continue;
    const Vec3<double> scale(std::exp(m.log_scales[3 * i]), std::exp(m.log_scales[3 * i + 1]),
                             std::exp(m.log_scales[3 * i + 2]));
    const Vec4<double> q(m.quats[4 * i], m.quats[4 * i + 1], m.quats[4 * i + 2], m.quats[4 * i + 3]);
    const Sym2<double> cov = covariance_2d(mc, covariance_3d(scale, quat_to_rotmat(q)), rotation_cw,
                                           double(camera.fx), double(camera.fy),
                                           double(camera.tan_half_fov_x()), double(camera.tan_half_fov_y()));
    Vec3<double> conic;
    if (!invert_covariance_2d(cov, conic)) continue;
    const Vec2<double> p = project_to_pixel(mc, double(camera.fx), double(camera.fy),
                                            double(camera.cx), double(camera.cy));
    Splat s{mc.z, p.x, p.y, conic.x, conic.y, conic.z, 1 / (1 + std::exp(-m.logits[i])), {}, {}};
    s.rect = reference_tile_rect(float(p.x), float(p.y), screen_radius(cov), grid);
    if (s.rect.count() == 0) continue;
    const Vec3<double> dir = glm::normalize(mean - center);
    const Vec3<double> rgb = sh_evaluate(degree, &m.sh[i * k_count * 3], dir);
    for (int c = 0; c < 3; ++c) s.color[c] = std::max(rgb[c] + 0.5, 0.0);
    splats.push_back(s);
  }
  std::stable_sort(splats.begin(), splats.end(), [](const Splat& a, const Splat& b) { return a.depth < b.depth; });

  double loss = 0;
  for (int y = 0; y < camera.height; ++y)
    for (int px = 0; px < camera.width; ++px) {
      auto acc = CompositeAccum<double>::start();
      bool finished = false;
      for (const Splat& s : splats) {
        const int tx = px / kTileSize, ty = y / kTileSize;
        if (tx < s.rect.x0 || tx >= s.rect.x1 || ty < s.rect.y0 || ty >= s.rect.y1) continue;
        const double dx = s.mx - px, dy = s.my - y;
        const double power = -0.5 * (s.a * dx * dx + s.c * dy * dy) - s.b * dx * dy;
        const double alpha = std::min(double(kMaxAlpha), s.opacity * std::exp(power));
        composite_step(acc, power <= 0 && alpha >= double(kMinAlpha), alpha, s.color[0], s.color[1],
                       s.color[2], s.depth, finished);
        if (finished) break;
      }
      const std::size_t p = std::size_t(y) * camera.width + px;
      for (int c = 0; c < 3; ++c) loss += weights[3 * p + c] * composite_finish(acc, c, double(background[c]));
    }
  return loss;
}

struct GroupSpan {
  const char* name;
  std::size_t first, count;
};

// The rasterizer's render and gradients for L = Σ W·I, W random from `seed` (the pose's too
// when `with_camera_pose`), on a coloured background.
struct AnalyticGradients {
  RenderSettings settings;
  std::vector<double> weights;
  RenderResult forward;
  RasterGradients grads;
};

AnalyticGradients analytic_gradients(const GaussianModel& model, const Camera& camera, unsigned seed,
                                     bool with_camera_pose) {
  AnalyticGradients a;
  a.settings.background[0] = 0.1f;
  a.settings.background[1] = 0.7f;
  a.settings.background[2] = 0.4f;
  a.weights = test::random_vector(std::size_t(3) * camera.width * camera.height, seed);
  Rasterizer rasterizer;
  rasterizer.render(model, camera, a.settings, a.forward);
  Image v_color(camera.width, camera.height, 3);
  for (std::size_t i = 0; i < a.weights.size(); ++i) v_color.data[i] = float(a.weights[i]);
  a.grads.with_camera_pose = with_camera_pose;
  rasterizer.backward(model, camera, a.settings, a.forward, v_color, a.grads);
  return a;
}

void check_pipeline_gradient(const GaussianModel& model, const Camera& camera, unsigned seed,
                             const std::string& what) {
  const AnalyticGradients a = analytic_gradients(model, camera, seed, false);
  const RenderSettings& settings = a.settings;
  const std::vector<double>& weights = a.weights;
  const RenderResult& forward = a.forward;
  const std::vector<double> analytic = flatten(a.grads.params);

  const std::vector<double> x = flatten(model);
  const std::size_t n = model.size();
  auto loss = [&](const std::vector<double>& params) {
    return std::vector<double>{reference_loss(params, n, model.sh_degree, camera, weights, settings.background)};
  };
  // The float render and the double reference agree on the value itself.
  double float_loss = 0;
  for (std::size_t i = 0; i < weights.size(); ++i) float_loss += weights[i] * forward.color.data[i];
  EXPECT_NEAR(float_loss, loss(x)[0], 1e-4 * (1 + std::abs(float_loss))) << what;

  const std::vector<double> numeric = test::numeric_vjp(loss, x, {1.0}, 1e-6);
  const std::size_t k3 = std::size_t(model.sh_coefficients()) * 3;
  const GroupSpan groups[] = {{"means", 0, 3 * n},          {"log_scales", 3 * n, 3 * n},
                              {"quats", 6 * n, 4 * n},      {"opacity", 10 * n, n},
                              {"sh", 11 * n, k3 * n}};
  for (const GroupSpan& g : groups) {
    double diff = 0, norm = 0, max_abs = 0;
    for (std::size_t i = g.first; i < g.first + g.count; ++i) {
      diff += (analytic[i] - numeric[i]) * (analytic[i] - numeric[i]);
      norm += numeric[i] * numeric[i];
      max_abs = std::max(max_abs, std::abs(numeric[i]));
    }
    ASSERT_GT(norm, 0) << what << " " << g.name << ": the scene must exercise this group";
    EXPECT_LT(std::sqrt(diff / norm), 2e-3) << what << " " << g.name;
    for (std::size_t i = g.first; i < g.first + g.count; ++i)
      EXPECT_NEAR(analytic[i], numeric[i], 5e-3 * max_abs) << what << " " << g.name << " entry " << i - g.first;
  }
  // Random direction: ⟨∇L, δ⟩ against the directional difference.
  const std::vector<double> direction = test::random_vector(x.size(), seed + 99);
  std::vector<double> plus = x, minus = x;
  const double eps = 1e-6;
  for (std::size_t i = 0; i < x.size(); ++i) {
    plus[i] += eps * direction[i];
    minus[i] -= eps * direction[i];
  }
  const double numeric_dot = (loss(plus)[0] - loss(minus)[0]) / (2 * eps);
  EXPECT_NEAR(test::dot(analytic, direction), numeric_dot, 2e-3 * std::abs(numeric_dot) + 1e-4) << what;
}

GaussianModel scene_model(unsigned seed, int count, float extent, float min_scale, float max_scale) {
  GaussianModel m = test::random_model(count, 3, seed, extent, min_scale, max_scale);
  // Opacities in a range that avoids the 0.99 clamp's kink (tested separately).
  for (float& o : m.opacity_logits) o = std::clamp(o, -2.0f, 2.5f);
  return m;
}

TEST(PipelineGradient, OverlappingGaussians) {
  const Camera cam = test::looking_at_origin(40, 28, 3.0f, 0.8f);
  check_pipeline_gradient(scene_model(11, 12, 0.5f, 0.08f, 0.3f), cam, 1, "overlapping");
}

TEST(PipelineGradient, GaussiansAcrossTheImageBorder) {
  const Camera cam = test::looking_at_origin(36, 30, 3.0f, 0.8f);
  GaussianModel m = scene_model(12, 10, 0.3f, 0.08f, 0.25f);
  for (std::size_t i = 0; i < m.size(); ++i) m.means[3 * i] += (i % 2 ? 1.0f : -1.0f) * 1.05f;  // near the sides
  check_pipeline_gradient(m, cam, 2, "border");
}

// The gradient of the camera's pose, through a correction (quaternion q, translation τ)
// applied to it, against central differences of the double reference render.
void check_pose_gradient(const GaussianModel& model, const Camera& camera, unsigned seed, const std::string& what) {
  const AnalyticGradients a = analytic_gradients(model, camera, seed, true);
  const RenderSettings& settings = a.settings;
  const std::vector<double>& weights = a.weights;
  const RasterGradients& grads = a.grads;

  const Mat3<double> rotation0(camera.camera_from_world_rotation);
  const Vec3<double> translation0(camera.camera_from_world_translation);
  const Vec4<double> identity(1, 0, 0, 0);
  Vec4<double> v_q;
  Vec3<double> v_tau;
  apply_pose_correction_vjp(identity, rotation0, translation0, Mat3<double>(grads.camera_pose.rotation),
                            Vec3<double>(grads.camera_pose.translation), v_q, v_tau);

  const std::vector<double> params = flatten(model);
  auto loss = [&](const std::vector<double>& correction) {
    DoublePose pose;
    apply_pose_correction(Vec4<double>(correction[0], correction[1], correction[2], correction[3]),
                          Vec3<double>(correction[4], correction[5], correction[6]), rotation0, translation0,
                          pose.rotation, pose.translation);
    return std::vector<double>{
        reference_loss(params, model.size(), model.sh_degree, camera, weights, settings.background, &pose)};
  };
  const std::vector<double> at_identity = {1, 0, 0, 0, 0, 0, 0};
  const std::vector<double> numeric = test::numeric_vjp(loss, at_identity, {1.0}, 1e-6);
  const double analytic[7] = {v_q[0], v_q[1], v_q[2], v_q[3], v_tau[0], v_tau[1], v_tau[2]};
  double norm = 0;
  for (double g : numeric) norm = std::max(norm, std::abs(g));
  ASSERT_GT(norm, 0) << what;
  for (int k = 0; k < 7; ++k) EXPECT_NEAR(analytic[k], numeric[std::size_t(k)], 5e-3 * norm) << what << " entry " << k;
}

TEST(PipelineGradient, CameraPose) {
  check_pose_gradient(scene_model(11, 12, 0.5f, 0.08f, 0.3f), test::looking_at_origin(40, 28, 3.0f, 0.8f), 5,
                      "overlapping");
  GaussianModel border = scene_model(12, 10, 0.3f, 0.08f, 0.25f);
  for (std::size_t i = 0; i < border.size(); ++i) border.means[3 * i] += (i % 2 ? 1.0f : -1.0f) * 1.05f;
  check_pose_gradient(border, test::looking_at_origin(36, 30, 3.0f, 0.8f), 6, "border");
}

TEST(PipelineGradient, NearlyDegenerateGaussians) {
  const Camera cam = test::looking_at_origin(32, 32, 3.0f, 0.8f);
  GaussianModel m = scene_model(13, 10, 0.4f, 0.05f, 0.3f);
  for (std::size_t i = 0; i < m.size(); i += 2) m.log_scales[3 * i + 1] = std::log(2e-4f);  // very flat
  for (std::size_t i = 1; i < m.size(); i += 4)
    for (int a = 0; a < 3; ++a) m.log_scales[3 * i + a] = std::log(3e-3f);  // sub-pixel
  check_pipeline_gradient(m, cam, 3, "degenerate");
}

}  // namespace
}  // namespace splat
