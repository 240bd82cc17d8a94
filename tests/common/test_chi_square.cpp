// The one chi-square implementation: upper tail against closed forms and the CDF, and the
// per-dof thresholds the tracker precomputes equal to the quantile they stand for.
#include <gtest/gtest.h>

#include <cmath>

#include "common/chi_square.hpp"

namespace st {
namespace {

TEST(ChiSquare, UpperTailMatchesClosedFormsAndTheCdf) {
  for (double x : {0.1, 1.0, 3.0, 10.0, 40.0}) {
    EXPECT_NEAR(chiSquareUpperTail(x, 1), std::erfc(std::sqrt(x / 2)), 1e-13) << x;
    EXPECT_NEAR(chiSquareUpperTail(x, 2), std::exp(-x / 2), 1e-13) << x;
    // Q(4, x) = exp(-x/2) (1 + x/2).
    EXPECT_NEAR(chiSquareUpperTail(x, 4), std::exp(-x / 2) * (1 + x / 2), 1e-13) << x;
    for (int k : {3, 7, 37}) EXPECT_NEAR(chiSquareUpperTail(x, k) + chiSquareCdf(x, k), 1.0, 1e-12);
  }
  EXPECT_EQ(chiSquareUpperTail(0.0, 3), 1.0);
  EXPECT_EQ(chiSquareUpperTail(-1.0, 3), 1.0);
}

TEST(ChiSquare, ThresholdsAreTheUpperQuantilesPerDof) {
  const ChiSquareThresholds t(1e-3, 37);
  EXPECT_EQ(t.maxDof(), 37);
  for (int k = 1; k <= 37; ++k) {
    EXPECT_EQ(t(k), chiSquareQuantile(1.0 - 1e-3, k)) << k;
    EXPECT_NEAR(chiSquareUpperTail(t(k), k), 1e-3, 1e-12) << k;
  }
  EXPECT_NEAR(t(3), 16.26623619623813, 1e-9);  // printed tables: chi2(3) at 0.999
}

}  // namespace
}  // namespace st
