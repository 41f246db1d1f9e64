// Spherical harmonics: known values and orthonormality of the basis over the sphere.
#include <gtest/gtest.h>

#include <cmath>

#include "splat/core/spherical_harmonics.hpp"

namespace splat {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(SphericalHarmonics, DegreeZeroIsConstant) {
  const double coeffs[3] = {1.0, -2.0, 0.5};
  const glm::dvec3 v = sh_evaluate(0, coeffs, glm::dvec3(0.6, 0.0, 0.8));
  EXPECT_DOUBLE_EQ(v.x, kShC0);
  EXPECT_DOUBLE_EQ(v.y, -2.0 * kShC0);
  EXPECT_DOUBLE_EQ(v.z, 0.5 * kShC0);
}

TEST(SphericalHarmonics, ValuesAlongTheZAxis) {
  double b[16];
  sh_basis(3, glm::dvec3(0, 0, 1), b);
  // Only the zonal (m = 0) functions are non-zero on the pole: Y1,0 = sqrt(3/4π),
  // Y2,0 = sqrt(5/4π), Y3,0 = sqrt(7/4π).
  EXPECT_NEAR(b[2], std::sqrt(3 / (4 * kPi)), 1e-12);
  EXPECT_NEAR(b[6], std::sqrt(5 / (4 * kPi)), 1e-12);
  EXPECT_NEAR(b[12], std::sqrt(7 / (4 * kPi)), 1e-12);
  for (int k : {1, 3, 4, 5, 7, 8, 9, 10, 11, 13, 14, 15}) EXPECT_NEAR(b[k], 0, 1e-12) << k;
}

TEST(SphericalHarmonics, SignConventionOfBandOne) {
  // The reference rasterizer's band 1 is (−y, z, −x) · C1.
  double b[16];
  sh_basis(1, glm::dvec3(1, 0, 0), b);
  EXPECT_NEAR(b[3], -kShC1, 1e-15);
  sh_basis(1, glm::dvec3(0, 1, 0), b);
  EXPECT_NEAR(b[1], -kShC1, 1e-15);
}

TEST(SphericalHarmonics, BasisIsOrthonormalOverTheSphere) {
  // ∫ Yᵢ Yⱼ dω = δᵢⱼ, by a midpoint rule in (cos θ, φ): exact in φ for these band-limited
  // products, second order in cos θ (error about 4e-5 on this grid).
  constexpr int kTheta = 600, kPhi = 64;
  double gram[16][16] = {};
  for (int i = 0; i < kTheta; ++i) {
    const double ct = -1.0 + (i + 0.5) * 2.0 / kTheta, st = std::sqrt(1 - ct * ct);
    for (int j = 0; j < kPhi; ++j) {
      const double phi = (j + 0.5) * 2 * kPi / kPhi;
      double b[16];
      sh_basis(3, glm::dvec3(st * std::cos(phi), st * std::sin(phi), ct), b);
      const double dw = (2.0 / kTheta) * (2 * kPi / kPhi);
      for (int a = 0; a < 16; ++a)
        for (int c = 0; c < 16; ++c) gram[a][c] += b[a] * b[c] * dw;
    }
  }
  for (int a = 0; a < 16; ++a)
    for (int c = 0; c < 16; ++c) EXPECT_NEAR(gram[a][c], a == c ? 1.0 : 0.0, 1e-4) << a << "," << c;
}

TEST(SphericalHarmonics, EvaluateSumsBasisTimesCoefficients) {
  double coeffs[16 * 3];
  for (int i = 0; i < 48; ++i) coeffs[i] = std::sin(1.7 * i + 0.3);
  const glm::dvec3 dir = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
  double b[16];
  sh_basis(3, dir, b);
  for (int degree = 0; degree <= 3; ++degree) {
    glm::dvec3 expected(0);
    for (int k = 0; k < (degree + 1) * (degree + 1); ++k)
      for (int c = 0; c < 3; ++c) expected[c] += b[k] * coeffs[3 * k + c];
    const glm::dvec3 got = sh_evaluate(degree, coeffs, dir);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expected[c], 1e-12);
  }
}

}  // namespace
}  // namespace splat
