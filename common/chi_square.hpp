/// @file chi_square.hpp
/// The chi-square distribution, written once: the filters' NEES/NIS bands (fusion/), the
/// identification's residual test (sensors/identify/verify.cpp) and the tracker's gates
/// (sensors/tracking/) all use these functions.
///
/// Exact to ~1e-12 relative: the regularized incomplete gamma function P(k/2, x/2) by its
/// series / Lentz continued fraction (Numerical Recipes 3rd ed. sec. 6.2); the quantile
/// inverts it by safeguarded Halley iteration started from Wilson-Hilferty. The quantile
/// iterates: per-frame code precomputes the thresholds it needs (ChiSquareThresholds).
#pragma once
#include <vector>

namespace st {

/// Regularized lower incomplete gamma P(a, x) = gamma(a, x) / Gamma(a), a > 0, x >= 0.
double regularizedGammaP(double a, double x);

/// Its complement Q(a, x) = 1 - P(a, x), accurate in the upper tail.
double regularizedGammaQ(double a, double x);

/// CDF of the chi-square distribution with `dof` (> 0, need not be an integer) at x.
double chiSquareCdf(double x, double dof);

/// Upper tail P(X > x), X ~ chi-square(dof): accurate where 1 - chiSquareCdf underflows.
/// 1 for x <= 0 or dof <= 0.
double chiSquareUpperTail(double x, double dof);

/// Quantile: the x with chiSquareCdf(x, dof) = p, for p in (0, 1); NaN outside.
double chiSquareQuantile(double p, double dof);

/// Upper-tail thresholds x(dof) with P(X > x) = alpha for dof = 1 .. max_dof, computed once
/// (the quantile iterates, a per-frame gate must not).
class ChiSquareThresholds {
 public:
  ChiSquareThresholds() = default;
  ChiSquareThresholds(double alpha, int max_dof);
  /// The threshold for `dof` in [1, maxDof()] (a bug otherwise: ST_ASSERT).
  double operator()(int dof) const;
  int maxDof() const { return static_cast<int>(x_.size()); }

 private:
  std::vector<double> x_;
};

}  // namespace st
