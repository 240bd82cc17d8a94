/// @file consistency.hpp
/// Chi-square distribution and the NEES/NIS consistency bands used to test filters
/// (Bar-Shalom, Li & Kirubarajan, Estimation with Applications to Tracking and Navigation,
/// sec. 5.4): for M Monte Carlo runs of a consistent filter, the run-averaged NEES of an
/// n-state error is chi-square with M*n degrees of freedom divided by M.
///
/// The chi-square distribution itself lives in common/chi_square.hpp (one implementation for
/// the filters, the identification and the tracker).
#pragma once
#include <vector>

#include "common/chi_square.hpp"

namespace st {

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
