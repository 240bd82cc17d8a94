/// @file consistency.hpp
/// Chi-square distribution and the NEES/NIS consistency bands used to test filters
/// (Bar-Shalom, Li & Kirubarajan, Estimation with Applications to Tracking and Navigation,
/// sec. 5.4): for M Monte Carlo runs of a consistent filter, the run-averaged NEES of an
/// n-state error is chi-square with M*n degrees of freedom divided by M.
///
/// The quantile is exact to ~1e-12 relative: it inverts the regularized lower incomplete
/// gamma function P(k/2, x/2) (series / Lentz continued fraction, Numerical Recipes 3rd ed.
/// sec. 6.2) by safeguarded Halley iteration started from Wilson-Hilferty.
#pragma once
#include <vector>

namespace st {

/// Regularized lower incomplete gamma P(a, x) = gamma(a, x) / Gamma(a), a > 0, x >= 0.
double regularizedGammaP(double a, double x);

/// Its complement Q(a, x) = 1 - P(a, x), accurate in the upper tail.
double regularizedGammaQ(double a, double x);

/// CDF of the chi-square distribution with `dof` (> 0, need not be an integer) at x.
double chiSquareCdf(double x, double dof);

/// Quantile: the x with chiSquareCdf(x, dof) = p, for p in (0, 1).
double chiSquareQuantile(double p, double dof);

/// Two-sided probability band [lo, hi] of a statistic.
struct ChiSquareBand {
  double lo = 0;
  double hi = 0;
  bool contains(double v) const { return v >= lo && v <= hi; }
};

/// Band of the average over `runs` independent chi-square(dof) values, holding it with
/// probability `prob` (two-sided, equal tails): chi2(runs*dof) quantiles / runs.
ChiSquareBand averagedChiSquareBand(double dof, int runs, double prob = 0.95);

/// Fraction of `values` inside `band` (0 for an empty vector).
double fractionInside(const std::vector<double>& values, const ChiSquareBand& band);

}  // namespace st
