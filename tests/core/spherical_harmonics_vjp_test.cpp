// The SH VJP (coefficients and direction) against central finite differences in double.
#include <gtest/gtest.h>

#include "tests/gradient_check.hpp"
#include "splat/core/spherical_harmonics.hpp"

namespace splat {
namespace {

TEST(SphericalHarmonicsVjp, CoefficientsAndDirectionEveryDegree) {
  for (int degree = 0; degree <= 3; ++degree) {
    const int k = (degree + 1) * (degree + 1);
    // Inputs: coefficients [k, 3], then the direction (not necessarily unit: the polynomial
    // basis is differentiated as is).
    std::vector<double> x = test::random_vector(3 * k + 3, 10 + degree);
    auto f = [&](const std::vector<double>& in) {
      const glm::dvec3 d(in[3 * k], in[3 * k + 1], in[3 * k + 2]);
      const glm::dvec3 c = sh_evaluate(degree, in.data(), d);
      return std::vector<double>{c.x, c.y, c.z};
    };
    const std::vector<double> v = test::random_vector(3, 20 + degree);
    std::vector<double> analytic(3 * k, 0.0);
    const glm::dvec3 dir(x[3 * k], x[3 * k + 1], x[3 * k + 2]);
    const glm::dvec3 v_dir = sh_evaluate_vjp(degree, x.data(), dir, glm::dvec3(v[0], v[1], v[2]), analytic.data());
    analytic.push_back(v_dir.x);
    analytic.push_back(v_dir.y);
    analytic.push_back(v_dir.z);
    test::expect_vjp_matches(f, x, v, analytic, "sh degree " + std::to_string(degree));
  }
}

}  // namespace
}  // namespace splat
