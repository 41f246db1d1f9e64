// Every projection stage's VJP against central finite differences in double.
#include <gtest/gtest.h>

#include "tests/gradient_check.hpp"
#include "splat/raster/projection_math.hpp"

namespace splat {
namespace {

using test::expect_vjp_matches;
using test::random_vector;
using D = double;

Mat3<D> mat_from(const std::vector<D>& x, std::size_t offset) {
  Mat3<D> m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) at(m, r, c) = x[offset + 3 * r + c];
  return m;
}
void mat_to(const Mat3<D>& m, std::vector<D>& out) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out.push_back(at(m, r, c));
}

TEST(ProjectionVjp, QuaternionToRotation) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    std::vector<D> q = random_vector(4, seed);
    auto f = [](const std::vector<D>& x) {
      std::vector<D> out;
      mat_to(quat_to_rotmat(Vec4<D>(x[0], x[1], x[2], x[3])), out);
      return out;
    };
    const std::vector<D> v = random_vector(9, seed + 100);
    const Vec4<D> g = quat_to_rotmat_vjp(Vec4<D>(q[0], q[1], q[2], q[3]), mat_from(v, 0));
    expect_vjp_matches(f, q, v, {g[0], g[1], g[2], g[3]}, "quat_to_rotmat");
  }
}

TEST(ProjectionVjp, Covariance3d) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    // Inputs: scale (3) then a free 3x3 matrix standing for R.
    std::vector<D> x = random_vector(12, seed);
    for (int a = 0; a < 3; ++a) x[a] = std::exp(x[a]);
    if (seed == 5) x[2] = 1e-4;  // nearly flat
    auto f = [](const std::vector<D>& in) {
      std::vector<D> out;
      mat_to(covariance_3d(Vec3<D>(in[0], in[1], in[2]), mat_from(in, 3)), out);
      return out;
    };
    const std::vector<D> v = random_vector(9, seed + 100);
    Vec3<D> v_scale;
    Mat3<D> v_rotation;
    covariance_3d_vjp(Vec3<D>(x[0], x[1], x[2]), mat_from(x, 3), mat_from(v, 0), v_scale, v_rotation);
    std::vector<D> analytic = {v_scale[0], v_scale[1], v_scale[2]};
    mat_to(v_rotation, analytic);
    expect_vjp_matches(f, x, v, analytic, "covariance_3d");
  }
}

// Inputs: camera-space mean (3), world covariance (9, symmetrised inside).
void check_covariance_2d(const Vec3<D>& mean, unsigned seed, const std::string& what) {
  const Mat3<D> rotation = quat_to_rotmat(Vec4<D>(0.9, 0.2, -0.3, 0.1));
  const D fx = 300, fy = 280, tan_x = 0.5, tan_y = 0.45;
  std::vector<D> x = {mean.x, mean.y, mean.z};
  const std::vector<D> a = random_vector(9, seed);
  Mat3<D> cov = mat_from(a, 0);
  cov = cov * glm::transpose(cov) * 0.01;  // SPD
  mat_to(cov, x);
  auto f = [&](const std::vector<D>& in) {
    const Mat3<D> c = mat_from(in, 3);
    const Sym2<D> s = covariance_2d(Vec3<D>(in[0], in[1], in[2]), (c + glm::transpose(c)) * 0.5,
                                    rotation, fx, fy, tan_x, tan_y);
    return std::vector<D>{s.xx, s.xy, s.yy};
  };
  const std::vector<D> v = random_vector(3, seed + 7);
  Vec3<D> v_mean;
  Mat3<D> v_cov;
  covariance_2d_vjp(Vec3<D>(x[0], x[1], x[2]), cov, rotation, fx, fy, tan_x, tan_y,
                    Sym2<D>{v[0], v[1], v[2]}, v_mean, v_cov);
  // The function symmetrises its matrix input, so the matching VJP is the symmetric part.
  const Mat3<D> v_sym = (v_cov + glm::transpose(v_cov)) * 0.5;
  std::vector<D> analytic = {v_mean.x, v_mean.y, v_mean.z};
  mat_to(v_sym, analytic);
  expect_vjp_matches(f, x, v, analytic, what, 1e-6, 1e-7);
}

TEST(ProjectionVjp, Covariance2dInsideTheView) { check_covariance_2d({0.3, -0.2, 2.5}, 1, "inside"); }
TEST(ProjectionVjp, Covariance2dClampedInX) { check_covariance_2d({3.0, 0.1, 2.0}, 2, "clamped x"); }
TEST(ProjectionVjp, Covariance2dClampedInY) { check_covariance_2d({-0.1, -4.0, 2.2}, 3, "clamped y"); }

// Σ' as a function of the camera rotation W alone (the camera-space mean held fixed: its
// own dependence on W is camera_pose_vjp's).
TEST(ProjectionVjp, Covariance2dCameraRotation) {
  const D fx = 300, fy = 280, tan_x = 0.5, tan_y = 0.45;
  for (const Vec3<D>& mean : {Vec3<D>(0.3, -0.2, 2.5), Vec3<D>(3.0, 0.1, 2.0)}) {  // inside, clamped
    const std::vector<D> a = random_vector(9, 4);
    Mat3<D> cov = mat_from(a, 0);
    cov = cov * glm::transpose(cov) * 0.01;
    std::vector<D> x;
    mat_to(quat_to_rotmat(Vec4<D>(0.9, 0.2, -0.3, 0.1)), x);
    for (D& w : x) w += 0.05 * random_vector(1, unsigned(&w - x.data()) + 20)[0];  // not orthonormal
    auto f = [&](const std::vector<D>& in) {
      const Sym2<D> s = covariance_2d(mean, cov, mat_from(in, 0), fx, fy, tan_x, tan_y);
      return std::vector<D>{s.xx, s.xy, s.yy};
    };
    const std::vector<D> v = random_vector(3, 9);
    Vec3<D> v_mean;
    Mat3<D> v_cov, v_rotation;
    covariance_2d_vjp(mean, cov, mat_from(x, 0), fx, fy, tan_x, tan_y, Sym2<D>{v[0], v[1], v[2]}, v_mean,
                      v_cov, &v_rotation);
    std::vector<D> analytic;
    mat_to(v_rotation, analytic);
    expect_vjp_matches(f, x, v, analytic, "covariance_2d w.r.t. W", 1e-6, 1e-7);
  }
}

// Inputs W (9, free) and t (3); outputs the camera-space mean W m + t and the centre −Wᵀ t.
TEST(ProjectionVjp, CameraPose) {
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const std::vector<D> x = random_vector(12, seed);
    const Vec3<D> mean(0.4, -1.2, 2.3);
    auto f = [&](const std::vector<D>& in) {
      const Mat3<D> w = mat_from(in, 0);
      const Vec3<D> t(in[9], in[10], in[11]);
      const Vec3<D> m = w * mean + t, c = -(glm::transpose(w) * t);
      return std::vector<D>{m.x, m.y, m.z, c.x, c.y, c.z};
    };
    const std::vector<D> v = random_vector(6, seed + 30);
    Mat3<D> v_rotation(0.0);
    Vec3<D> v_translation(0.0);
    camera_pose_vjp(mean, mat_from(x, 0), Vec3<D>(x[9], x[10], x[11]), Vec3<D>(v[0], v[1], v[2]),
                    Vec3<D>(v[3], v[4], v[5]), v_rotation, v_translation);
    std::vector<D> analytic;
    mat_to(v_rotation, analytic);
    for (int a = 0; a < 3; ++a) analytic.push_back(v_translation[a]);
    expect_vjp_matches(f, x, v, analytic, "camera_pose");
  }
}

// Inputs the correction's quaternion (4) and translation (3); outputs W (9) and t (3); about
// the camera centre and about a pivot in front of it.
TEST(ProjectionVjp, PoseCorrection) {
  const Mat3<D> rotation0 = quat_to_rotmat(Vec4<D>(0.7, -0.3, 0.2, 0.5));
  const Vec3<D> translation0(0.3, -0.8, 4.1);
  for (unsigned seed = 1; seed <= 4; ++seed) {
    const Vec3<D> pivot = seed % 2 == 0 ? Vec3<D>(0.2, -0.1, 3.7) : Vec3<D>(0.0);
    std::vector<D> x = random_vector(7, seed, 0.1);
    x[0] += 1.0;  // near the identity, as corrections are
    auto f = [&](const std::vector<D>& in) {
      Mat3<D> w;
      Vec3<D> t;
      apply_pose_correction(Vec4<D>(in[0], in[1], in[2], in[3]), Vec3<D>(in[4], in[5], in[6]), rotation0,
                            translation0, w, t, pivot);
      std::vector<D> out;
      mat_to(w, out);
      for (int a = 0; a < 3; ++a) out.push_back(t[a]);
      return out;
    };
    const std::vector<D> v = random_vector(12, seed + 40);
    Vec4<D> v_q;
    Vec3<D> v_tau;
    apply_pose_correction_vjp(Vec4<D>(x[0], x[1], x[2], x[3]), rotation0, translation0, mat_from(v, 0),
                              Vec3<D>(v[9], v[10], v[11]), v_q, v_tau, pivot);
    expect_vjp_matches(f, x, v, {v_q[0], v_q[1], v_q[2], v_q[3], v_tau[0], v_tau[1], v_tau[2]},
                       "pose correction");
  }
  // The identity correction leaves the pose unchanged, about any pivot; a turn about the
  // pivot keeps the pivot where it was in the camera's frame.
  const Vec3<D> pivot(0.2, -0.1, 3.7);
  Mat3<D> w;
  Vec3<D> t;
  apply_pose_correction(Vec4<D>(1, 0, 0, 0), Vec3<D>(0.0), rotation0, translation0, w, t, pivot);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(at(w, r, c), at(rotation0, r, c), 1e-15);
  EXPECT_NEAR(glm::length(t - translation0), 0.0, 1e-15);
  const Vec3<D> pivot_world = glm::transpose(rotation0) * (pivot - translation0);  // W₀ x + t₀ = p
  apply_pose_correction(Vec4<D>(0.9, 0.2, -0.3, 0.1), Vec3<D>(0.0), rotation0, translation0, w, t, pivot);
  EXPECT_NEAR(glm::length(w * pivot_world + t - pivot), 0.0, 1e-12);
}

TEST(ProjectionVjp, ConicFromCovariance) {
  for (unsigned seed = 1; seed <= 4; ++seed) {
    const std::vector<D> r = random_vector(3, seed);
    std::vector<D> x = {2.0 + r[0] * r[0], 0.5 * r[1], 1.0 + r[2] * r[2]};  // SPD
    if (seed == 4) x = {400.0, 0.0, 0.31};  // very flat on screen
    auto f = [](const std::vector<D>& in) {
      Vec3<D> conic(0.0);  // (set by the call; initialised for GCC 12's -Wmaybe-uninitialized)
      invert_covariance_2d(Sym2<D>{in[0], in[1], in[2]}, conic);
      return std::vector<D>{conic.x, conic.y, conic.z};
    };
    Vec3<D> conic(0.0);
    invert_covariance_2d(Sym2<D>{x[0], x[1], x[2]}, conic);
    const std::vector<D> v = random_vector(3, seed + 10);
    const Sym2<D> g = invert_covariance_2d_vjp(conic, Vec3<D>(v[0], v[1], v[2]));
    expect_vjp_matches(f, x, v, {g.xx, g.xy, g.yy}, "invert_covariance_2d", 1e-6, 1e-9);
  }
}

TEST(ProjectionVjp, PixelProjection) {
  const std::vector<D> x = {0.4, -0.7, 3.1};
  auto f = [](const std::vector<D>& in) {
    const Vec2<D> p = project_to_pixel(Vec3<D>(in[0], in[1], in[2]), 300.0, 250.0, 200.0, 150.0);
    return std::vector<D>{p.x, p.y};
  };
  const std::vector<D> v = {0.8, -1.3};
  const Vec3<D> g = project_to_pixel_vjp(Vec3<D>(x[0], x[1], x[2]), 300.0, 250.0, Vec2<D>(v[0], v[1]));
  expect_vjp_matches(f, x, v, {g.x, g.y, g.z}, "project_to_pixel");
}

}  // namespace
}  // namespace splat
