#include "app/montecarlo/stats.hpp"

#include <algorithm>
#include <cmath>

#include "common/errors.hpp"

namespace st::app::mc {

double mean(const std::vector<double>& v) {
  if (v.empty()) return NAN;
  double s = 0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}

double rms(const std::vector<double>& v) {
  if (v.empty()) return NAN;
  double s = 0;
  for (double x : v) s += x * x;
  return std::sqrt(s / static_cast<double>(v.size()));
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const double pos = q * static_cast<double>(v.size() - 1);
  const std::size_t i = static_cast<std::size_t>(std::floor(pos));
  if (i + 1 >= v.size()) return v.back();
  const double f = pos - static_cast<double>(i);
  return v[i] * (1 - f) + v[i + 1] * f;
}

Interval wilson95(std::size_t k, std::size_t n) {
  if (n == 0) return {0, 1};
  const double z = 1.959963984540054, nn = static_cast<double>(n);
  const double p = static_cast<double>(k) / nn;
  const double den = 1 + z * z / nn;
  const double centre = (p + z * z / (2 * nn)) / den;
  const double half = z * std::sqrt(p * (1 - p) / nn + z * z / (4 * nn * nn)) / den;
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

double cellNum(const Row& row, std::size_t col, const std::string& col_name) {
  if (col >= row.size())
    throw ProcessingError("trial row too short for column '" + col_name + "'");
  const std::string& s = row[col];
  if (s == "nan") return NAN;
  try {
    std::size_t used = 0;
    const double v = std::stod(s, &used);
    if (used == s.size()) return v;
  } catch (const std::exception&) {
  }
  throw ProcessingError("bad number '" + s + "' in trial column '" + col_name + "'");
}

}  // namespace st::app::mc
