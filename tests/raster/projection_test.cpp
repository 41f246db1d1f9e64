// Projection and 2D covariance against hand-computed cases.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "splat/raster/pixel_projection.hpp"
#include "splat/raster/project.hpp"
#include "splat/raster/projection_math.hpp"
#include "tests/test_support.hpp"

// The dilation and clamp constants are floats, as in the reference rasterizer.
constexpr double kDilation = double(splat::kCovarianceDilation);
constexpr double kClamp = double(splat::kJacobianClamp);

namespace splat {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(Projection, IdentityQuaternionGivesIdentityRotation) {
  const Mat3<double> r = quat_to_rotmat(Vec4<double>(1, 0, 0, 0));
  for (int c = 0; c < 3; ++c)
    for (int row = 0; row < 3; ++row) EXPECT_DOUBLE_EQ(r[c][row], c == row ? 1.0 : 0.0);
}

TEST(Projection, QuaternionIsNormalisedAndRotatesAboutItsAxis) {
  // 90 degrees about +z, given unnormalised (scaled by 3): x -> y, y -> -x.
  const double h = std::sqrt(0.5);
  const Mat3<double> r = quat_to_rotmat(Vec4<double>(3 * h, 0, 0, 3 * h));
  const Vec3<double> x_image = r * Vec3<double>(1, 0, 0);
  const Vec3<double> y_image = r * Vec3<double>(0, 1, 0);
  EXPECT_NEAR(x_image.x, 0, 1e-12);
  EXPECT_NEAR(x_image.y, 1, 1e-12);
  EXPECT_NEAR(y_image.x, -1, 1e-12);
  EXPECT_NEAR(y_image.y, 0, 1e-12);
  EXPECT_NEAR(glm::determinant(r), 1.0, 1e-12);
}

TEST(Projection, CovarianceOfRotatedAxisAlignedGaussian) {
  // Scales (2, 0.5, 1) rotated 90 degrees about z: the long axis now lies along y.
  const double h = std::sqrt(0.5);
  const Mat3<double> cov = covariance_3d(Vec3<double>(2, 0.5, 1), quat_to_rotmat(Vec4<double>(h, 0, 0, h)));
  EXPECT_NEAR(cov[0][0], 0.25, 1e-12);
  EXPECT_NEAR(cov[1][1], 4.0, 1e-12);
  EXPECT_NEAR(cov[2][2], 1.0, 1e-12);
  EXPECT_NEAR(cov[1][0], 0.0, 1e-12);
}

TEST(Projection, IsotropicGaussianOnTheAxis) {
  // Σ = s² I at (0, 0, z): Σ' = (f s / z)² I + 0.3 I.
  const double s = 0.1, z = 4, f = 500;
  const Mat3<double> cov = covariance_3d(Vec3<double>(s, s, s), Mat3<double>(1.0));
  const Sym2<double> c2 = covariance_2d(Vec3<double>(0, 0, z), cov, Mat3<double>(1.0), f, f, 0.5, 0.5);
  const double expected = (f * s / z) * (f * s / z) + kDilation;
  EXPECT_NEAR(c2.xx, expected, 1e-9);
  EXPECT_NEAR(c2.yy, expected, 1e-9);
  EXPECT_NEAR(c2.xy, 0, 1e-12);
}

TEST(Projection, OffAxisGaussianStretchesAlongTheOffset) {
  // At (x, 0, z) the Jacobian's first row is (f/z, 0, −f x/z²):
  // Σ'xx = s² f² / z² (1 + x²/z²) + 0.3, Σ'yy = s² f² / z² + 0.3, Σ'xy = 0.
  const double s = 0.1, x = 1, z = 4, f = 500;
  const Mat3<double> cov = covariance_3d(Vec3<double>(s, s, s), Mat3<double>(1.0));
  const Sym2<double> c2 = covariance_2d(Vec3<double>(x, 0, z), cov, Mat3<double>(1.0), f, f, 0.5, 0.5);
  EXPECT_NEAR(c2.xx, s * s * f * f / (z * z) * (1 + x * x / (z * z)) + kDilation, 1e-9);
  EXPECT_NEAR(c2.yy, s * s * f * f / (z * z) + kDilation, 1e-9);
  EXPECT_NEAR(c2.xy, 0, 1e-12);
}

TEST(Projection, JacobianIsClampedFarOutsideTheView) {
  // tan(fov/2) = 0.5: x/z is clamped to 0.65, so a Gaussian at x/z = 3 gets the Jacobian of
  // x/z = 0.65 (its 2D covariance equals that of a Gaussian at x = 0.65 z).
  const double s = 0.1, z = 4, f = 500;
  const Mat3<double> cov = covariance_3d(Vec3<double>(s, s, s), Mat3<double>(1.0));
  const Sym2<double> far = covariance_2d(Vec3<double>(3 * z, 0, z), cov, Mat3<double>(1.0), f, f, 0.5, 0.5);
  const double limit = kClamp * 0.5;
  const Sym2<double> at_limit =
      covariance_2d(Vec3<double>(limit * z, 0, z), cov, Mat3<double>(1.0), f, f, 0.5, 0.5);
  EXPECT_NEAR(far.xx, at_limit.xx, 1e-9);
  EXPECT_NEAR(far.xx, s * s * f * f / (z * z) * (1 + limit * limit) + kDilation, 1e-9);
}

TEST(Projection, ViewRotationIsApplied) {
  // A Gaussian long along world x, seen by a camera rolled 90 degrees about its z axis,
  // is long along the image y axis.
  const double f = 100, z = 5;
  const Mat3<double> cov = covariance_3d(Vec3<double>(1, 0.1, 0.1), Mat3<double>(1.0));
  const Mat3<double> roll = quat_to_rotmat(Vec4<double>(std::cos(kPi / 4), 0, 0, std::sin(kPi / 4)));
  const Sym2<double> c2 = covariance_2d(Vec3<double>(0, 0, z), cov, roll, f, f, 1.0, 1.0);
  EXPECT_NEAR(c2.yy, (f / z) * (f / z) * 1.0 + kDilation, 1e-9);
  EXPECT_NEAR(c2.xx, (f / z) * (f / z) * 0.01 + kDilation, 1e-9);
}

TEST(Projection, PixelPositionUsesReferencePixelCentres) {
  const Vec2<double> p = project_to_pixel(Vec3<double>(0, 0, 3), 100.0, 100.0, 200.0, 150.0);
  EXPECT_DOUBLE_EQ(p.x, 199.5);
  EXPECT_DOUBLE_EQ(p.y, 149.5);
  const Vec2<double> q = project_to_pixel(Vec3<double>(1, -2, 4), 100.0, 50.0, 200.0, 150.0);
  EXPECT_DOUBLE_EQ(q.x, 100.0 * 0.25 + 199.5);
  EXPECT_DOUBLE_EQ(q.y, 50.0 * -0.5 + 149.5);
}

// PixelProjection follows the official rounding; it must still be the same function as
// project_to_pixel (which the backward pass differentiates), for centred and off-centre
// principal points, up to float rounding.
TEST(Projection, ReferenceArithmeticPixelMatchesTheDirectFormula) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> coord(-1.5f, 1.5f);
  for (const float cx_offset : {0.0f, 13.25f}) {
    Camera camera = test::looking_at_origin(320, 240, 4.0f, 0.9f);
    camera.cx += cx_offset;
    camera.cy -= 0.5f * cx_offset;
    const PixelProjection pixel_of(camera);
    for (int i = 0; i < 1000; ++i) {
      const glm::vec3 p(coord(rng), coord(rng), coord(rng));
      const glm::dvec3 pc = glm::dmat3(camera.camera_from_world_rotation) * glm::dvec3(p) +
                            glm::dvec3(camera.camera_from_world_translation);
      const Vec2<double> exact = project_to_pixel(pc, double(camera.fx), double(camera.fy),
                                                  double(camera.cx), double(camera.cy));
      const Vec2<float> ours = pixel_of(p);
      EXPECT_NEAR(ours.x, exact.x, 1e-4) << i;
      EXPECT_NEAR(ours.y, exact.y, 1e-4) << i;
    }
  }
}

TEST(Projection, ConicAndRadius) {
  // Σ' = [[4, 0], [0, 4]]: conic 1/4 I; λmax = 4 + sqrt(max(0.1, 0)) → ceil(3·sqrt(4.316)) = 7.
  Vec3<double> conic;
  ASSERT_TRUE(invert_covariance_2d(Sym2<double>{4, 0, 4}, conic));
  EXPECT_DOUBLE_EQ(conic.x, 0.25);
  EXPECT_DOUBLE_EQ(conic.y, 0.0);
  EXPECT_DOUBLE_EQ(conic.z, 0.25);
  EXPECT_EQ(screen_radius(Sym2<double>{4, 0, 4}), 7);
  // [[9, 2], [2, 1]]: λmax = 5 + sqrt(25 − 5) = 9.472 → ceil(3·3.0777) = 10.
  EXPECT_EQ(screen_radius(Sym2<double>{9, 2, 1}), 10);
  EXPECT_FALSE(invert_covariance_2d(Sym2<double>{1, 1, 1}, conic));
}

TEST(Projection, NearPlaneCullsAtPointTwo) {
  GaussianModel m;
  m.resize(3);
  const float z_world[3] = {0.2f, 0.25f, -10.0f};  // camera at the origin: world z = camera z
  for (int i = 0; i < 3; ++i) {
    m.means[3 * i + 2] = z_world[i];
    m.quats[4 * i] = 1;
    m.log_scales[3 * i] = m.log_scales[3 * i + 1] = m.log_scales[3 * i + 2] = std::log(0.01f);
    m.opacity_logits[i] = 3;
  }
  const Camera cam = test::looking_at_origin(64, 64, 0.0f);
  ProjectedGaussians p;
  project_gaussians(m, cam, 0, p);
  EXPECT_EQ(p.radius[0], 0);  // z = 0.2 exactly: culled
  EXPECT_GT(p.radius[1], 0);  // z = 0.25: kept
  EXPECT_EQ(p.radius[2], 0);  // behind the camera
  EXPECT_FLOAT_EQ(p.splats[1].mean_x, 31.5f);
  EXPECT_FLOAT_EQ(p.splats[1].mean_y, 31.5f);
}

TEST(Projection, NonFiniteParametersAreCulledNotUndefined) {
  GaussianModel m = test::random_model(4, 0, 7, 0.5f);
  m.means[0] = std::nanf("");
  m.log_scales[3 * 1] = 200.0f;  // exp overflows to inf
  m.quats[4 * 2] = m.quats[4 * 2 + 1] = m.quats[4 * 2 + 2] = m.quats[4 * 2 + 3] = 0;  // 0/0
  ProjectedGaussians p;
  project_gaussians(m, test::looking_at_origin(64, 64), 0, p);
  EXPECT_EQ(p.radius[0], 0);
  EXPECT_EQ(p.radius[1], 0);
  EXPECT_EQ(p.radius[2], 0);
  EXPECT_EQ(p.tiles[0].count(), 0);
}

}  // namespace
}  // namespace splat
