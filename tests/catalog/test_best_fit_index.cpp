// Seed 000's best-fit star-pair ID (eqs. 7-10) against a brute-force scan and the k-vector,
// and the seed's claim that a 7th-degree polynomial follows the data better than its line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "catalog/best_fit_index.hpp"
#include "catalog/star_database.hpp"
#include "common/conventions.hpp"
#include "tests/catalog/catalog_fixture.hpp"

namespace st {
namespace {

TEST(BestFitIndex, RangeEqualsBruteForceOnRandomData) {
  std::mt19937_64 rng(7);
  for (int degree : {1, 7})
    for (std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(2), std::size_t(17),
                          std::size_t(5000)}) {
      // Clustered values (two Gaussians + duplicates): a poor fit, a long search, still exact.
      const std::vector<double> y = test::clusteredSortedValues(n, rng);
      const BestFitIndex bf(y, degree);
      std::uniform_real_distribution<double> u(-0.5, 1.8), w(0, 0.2);
      for (int q = 0; q < 2000; ++q) {
        const double lo = u(rng), hi = lo + w(rng);
        const auto r = bf.range(lo, hi);
        const auto [b, e] = test::bruteRange(y, lo, hi);
        if (b == e) {
          ASSERT_EQ(r.first, r.second);
        } else {
          ASSERT_EQ(r.first, b) << "degree " << degree << " n=" << n << " lo=" << lo;
          ASSERT_EQ(r.second, e) << "degree " << degree << " n=" << n << " hi=" << hi;
        }
      }
    }
}

TEST(BestFitIndex, SeventhDegreeFollowsTheRealPairsBetterAndBothEqualTheKVector) {
  const StarDatabase& db = test::hipDatabase15();
  std::vector<double> theta;
  theta.reserve(db.pairs().size());
  for (const StarPair& p : db.pairs()) theta.push_back(p.theta);
  const BestFitIndex line(theta, 1), poly(theta, 7);
  std::printf("[ info ] %zu pairs: max |k - i| %zu with the best-fit line (seed 000 eq. 8), %zu "
              "with the 7th-degree polynomial (eq. 10)\n",
              theta.size(), line.maxIndexError(), poly.maxIndexError());
  // Seed 000 Figs. 3-6: the polynomial describes the data better than the line.
  EXPECT_LT(poly.maxIndexError(), line.maxIndexError());
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> th(0, db.params().max_pair_angle);
  std::uniform_real_distribution<double> dl(0, arcsec2rad(60));
  for (int q = 0; q < 10000; ++q) {
    const double t = th(rng), d = dl(rng);
    const PairSlice s = db.pairsInRange(t - d, t + d);
    const std::size_t kb = std::size_t(s.begin - db.pairs().data());
    for (const BestFitIndex* bf : {&line, &poly}) {
      const auto r = bf->range(t - d, t + d);
      ASSERT_EQ(r.second - r.first, s.size()) << "degree " << bf->degree();
      if (s.size() > 0) {
        ASSERT_EQ(r.first, kb) << "degree " << bf->degree();
      }
    }
  }
}

}  // namespace
}  // namespace st
