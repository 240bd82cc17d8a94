#include "fusion/consistency.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace st {

ChiSquareBand averagedChiSquareBand(double dof, int runs, double prob) {
  const double tail = 0.5 * (1.0 - prob);
  const double n = dof * runs;
  return {chiSquareQuantile(tail, n) / runs, chiSquareQuantile(1.0 - tail, n) / runs};
}

double fractionInside(const std::vector<double>& values, const ChiSquareBand& band) {
  if (values.empty()) return 0.0;
  const auto inside =
      std::count_if(values.begin(), values.end(), [&](double v) { return band.contains(v); });
  return static_cast<double>(inside) / static_cast<double>(values.size());
}

}  // namespace st
