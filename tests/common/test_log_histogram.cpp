// LogHistogram: quantiles of a stream in fixed memory, within half a bin (0.5 %) of the
// exact order statistic; the run summaries of `live` rely on it for their percentiles.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "common/log_histogram.hpp"

namespace st {
namespace {

double exactQuantile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  const std::size_t i = std::min(v.size() - 1, std::size_t(std::ceil(p * double(v.size())) - 1));
  return v[i];
}

TEST(LogHistogram, QuantilesWithinHalfABinOfTheExactOrderStatistic) {
  std::mt19937_64 rng(11);
  std::lognormal_distribution<double> d(0.5, 1.5);  // arcsec-like errors over decades
  std::vector<double> v;
  LogHistogram h;
  for (int i = 0; i < 20000; ++i) {
    v.push_back(d(rng));
    h.add(v.back());
  }
  EXPECT_EQ(h.count(), v.size());
  EXPECT_EQ(h.max(), *std::max_element(v.begin(), v.end()));
  EXPECT_EQ(h.min(), *std::min_element(v.begin(), v.end()));
  for (double p : {0.01, 0.5, 0.9, 0.95, 0.99}) {
    const double exact = exactQuantile(v, p);
    EXPECT_NEAR(h.quantile(p) / exact, 1.0, 0.005) << "p " << p;
  }
}

TEST(LogHistogram, EmptyZeroAndOutOfRangeValues) {
  LogHistogram h;
  EXPECT_EQ(h.quantile(0.5), 0.0);
  h.add(0.0);
  h.add(std::nan(""));  // ignored
  h.add(1e12);          // beyond the last bin: bounded by the exact max
  EXPECT_EQ(h.count(), 2u);
  EXPECT_EQ(h.quantile(0.5), 0.0);
  EXPECT_EQ(h.quantile(1.0), 1e12);
}

}  // namespace
}  // namespace st
