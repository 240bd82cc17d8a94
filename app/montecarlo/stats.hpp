/// @file stats.hpp
/// Small statistics for the Monte Carlo summaries: mean, RMS, quantiles and the binomial
/// confidence interval of a rate.
#pragma once
#include <string>
#include <vector>

#include "app/montecarlo/experiment.hpp"

namespace st::app::mc {

double mean(const std::vector<double>& v);  ///< NaN when empty
double rms(const std::vector<double>& v);   ///< sqrt(mean(v^2)), NaN when empty
/// Quantile q in [0, 1] by linear interpolation of the sorted values; NaN when empty.
double quantile(std::vector<double> v, double q);

/// Wilson score interval (95 %) of a rate k/n: [lo, hi]. For k = 0 the upper end is about
/// 3.84 / n (close to the "rule of three" 3 / n).
struct Interval {
  double lo, hi;
};
Interval wilson95(std::size_t k, std::size_t n);

/// Numeric cell of a trial row (ProcessingError naming the column on a malformed value).
double cellNum(const Row& row, std::size_t col, const std::string& col_name = "");

}  // namespace st::app::mc
