#pragma once
// Finite-difference checks of vector-Jacobian products, in double precision.
//
// For f: Rⁿ → Rᵐ and a cotangent v ∈ Rᵐ, the VJP is vᵀJ. Its i-th entry is checked against
// the central difference (⟨v, f(x + h eᵢ)⟩ − ⟨v, f(x − h eᵢ)⟩) / 2h, and the whole vector
// by the random-direction identity ⟨vᵀJ, δ⟩ = (⟨v, f(x + εδ)⟩ − ⟨v, f(x − εδ)⟩) / 2ε.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace splat::test {

using VectorFunction = std::function<std::vector<double>(const std::vector<double>&)>;

inline double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

// Central-difference vᵀJ at x.
inline std::vector<double> numeric_vjp(const VectorFunction& f, const std::vector<double>& x,
                                       const std::vector<double>& v, double h = 1e-6) {
  std::vector<double> grad(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    std::vector<double> plus = x, minus = x;
    plus[i] += h;
    minus[i] -= h;
    grad[i] = (dot(v, f(plus)) - dot(v, f(minus))) / (2 * h);
  }
  return grad;
}

// Checks `analytic` (= vᵀJ) entry by entry, with tolerance atol + rtol·|numeric|, and with a
// random-direction dot product test.
inline void expect_vjp_matches(const VectorFunction& f, const std::vector<double>& x,
                               const std::vector<double>& v, const std::vector<double>& analytic,
                               const std::string& what, double rtol = 1e-6, double atol = 1e-8,
                               unsigned seed = 1) {
  ASSERT_EQ(analytic.size(), x.size()) << what;
  const std::vector<double> numeric = numeric_vjp(f, x, v);
  for (std::size_t i = 0; i < x.size(); ++i)
    EXPECT_NEAR(analytic[i], numeric[i], atol + rtol * std::abs(numeric[i]))
        << what << ": input " << i;
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  std::vector<double> direction(x.size());
  for (double& d : direction) d = normal(rng);
  const double eps = 1e-6;
  std::vector<double> plus = x, minus = x;
  for (std::size_t i = 0; i < x.size(); ++i) {
    plus[i] += eps * direction[i];
    minus[i] -= eps * direction[i];
  }
  const double numeric_dot = (dot(v, f(plus)) - dot(v, f(minus))) / (2 * eps);
  EXPECT_NEAR(dot(analytic, direction), numeric_dot, atol * 10 + rtol * 10 * std::abs(numeric_dot))
      << what << ": random-direction dot product";
}

inline std::vector<double> random_vector(std::size_t n, unsigned seed, double scale = 1.0) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, scale);
  std::vector<double> v(n);
  for (double& x : v) x = normal(rng);
  return v;
}

}  // namespace splat::test
