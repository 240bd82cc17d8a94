// Chi-square quantiles against table values and closed forms; NEES/NIS band helpers.
#include <gtest/gtest.h>

#include <cmath>

#include "fusion/consistency.hpp"

namespace st {
namespace {

TEST(Consistency, ChiSquareQuantileMatchesTables) {
  // Reference values (R: qchisq), 10+ significant digits.
  EXPECT_NEAR(chiSquareQuantile(0.95, 1), 3.841458820694124, 1e-10);
  EXPECT_NEAR(chiSquareQuantile(0.5, 1), 0.454936423119572, 1e-10);
  EXPECT_NEAR(chiSquareQuantile(0.95, 3), 7.814727903251178, 1e-10);
  EXPECT_NEAR(chiSquareQuantile(0.99, 6), 16.81189382977093, 1e-9);
  EXPECT_NEAR(chiSquareQuantile(0.05, 10), 3.940299136119769, 1e-10);
  EXPECT_NEAR(chiSquareQuantile(0.025, 100), 74.222, 1e-3);  // printed tables: 3 decimals
  EXPECT_NEAR(chiSquareQuantile(0.975, 100), 129.561, 1e-3);
}

TEST(Consistency, ChiSquareQuantileClosedFormForTwoDof) {
  // dof = 2 is exponential: x = -2 ln(1 - p).
  for (double p : {1e-9, 1e-4, 0.01, 0.3, 0.5, 0.9, 0.999, 1 - 1e-9}) {
    const double exact = -2.0 * std::log1p(-p);
    EXPECT_NEAR(chiSquareQuantile(p, 2), exact, 1e-9 * std::max(1.0, exact)) << p;
  }
}

TEST(Consistency, QuantileInvertsTheCdf) {
  for (double dof : {0.5, 1.0, 2.0, 3.0, 6.0, 17.5, 150.0, 300.0, 3000.0}) {
    for (double p : {1e-6, 0.0013, 0.025, 0.5, 0.975, 0.9973, 0.999999}) {
      const double x = chiSquareQuantile(p, dof);
      EXPECT_NEAR(chiSquareCdf(x, dof), p, 1e-10) << dof << " " << p;
    }
  }
  EXPECT_TRUE(std::isnan(chiSquareQuantile(0.0, 3)));
  EXPECT_TRUE(std::isnan(chiSquareQuantile(1.0, 3)));
}

TEST(Consistency, AveragedBandAndFraction) {
  const ChiSquareBand b = averagedChiSquareBand(2, 50, 0.95);  // chi2(100)/50
  EXPECT_NEAR(b.lo, chiSquareQuantile(0.025, 100) / 50, 1e-12);
  EXPECT_NEAR(b.hi, chiSquareQuantile(0.975, 100) / 50, 1e-12);
  EXPECT_DOUBLE_EQ(fractionInside({1.0, 2.0, 3.0, 2.5}, b), 0.5);
  EXPECT_DOUBLE_EQ(fractionInside({}, b), 0.0);
}

}  // namespace
}  // namespace st
