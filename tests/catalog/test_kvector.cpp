// k-vector (seed 000 eqs. 11-14) and the pair index against a brute-force scan.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "catalog/kvector.hpp"
#include "catalog/star_database.hpp"
#include "common/conventions.hpp"
#include "tests/catalog/catalog_fixture.hpp"

namespace st {
namespace {

TEST(KVector, RangeEqualsBruteForceOnRandomData) {
  std::mt19937_64 rng(7);
  for (std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(2), std::size_t(17),
                        std::size_t(5000)}) {
    // Clustered values (two Gaussians + duplicates) stress the linear k-vector line.
    const std::vector<double> y = test::clusteredSortedValues(n, rng);
    KVector kv;
    auto at = [&](std::size_t k) { return y[k]; };
    kv.build(n, at);
    std::uniform_real_distribution<double> u(-0.5, 1.8), w(0, 0.2);
    for (int q = 0; q < 2000; ++q) {
      const double lo = u(rng), hi = lo + w(rng);
      const auto r = kv.range(lo, hi, at);
      const auto [b, e] = test::bruteRange(y, lo, hi);
      if (b == e) {
        ASSERT_EQ(r.first, r.second);
      } else {
        ASSERT_EQ(r.first, b) << "n=" << n << " lo=" << lo;
        ASSERT_EQ(r.second, e) << "n=" << n << " hi=" << hi;
      }
    }
  }
}

TEST(StarDatabasePairs, KVectorRangeEqualsBruteForceOn10000Queries) {
  const StarDatabase& db = test::hipDatabase15();
  const auto& pairs = db.pairs();
  std::printf("[ info ] 15 deg / V<=6.5 database: %zu stars, %zu pairs, k-vector %zu entries\n",
              db.stars().size(), pairs.size(), db.pairKVector().size());
  ASSERT_GT(pairs.size(), 100000u);
  ASSERT_TRUE(std::is_sorted(pairs.begin(), pairs.end(),
                             [](const StarPair& a, const StarPair& b) { return a.theta < b.theta; }));
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> th(-deg2rad(0.5), db.params().max_pair_angle + deg2rad(0.5));
  std::uniform_real_distribution<double> dl(0, arcsec2rad(120));
  for (int q = 0; q < 10000; ++q) {
    const double t = th(rng), d = dl(rng);
    const PairSlice s = db.pairsInRange(t - d, t + d);
    // Reference: binary search over the (verified sorted) stored float thetas; every 100th
    // query also by a full linear scan.
    const auto cmp_lo = [](const StarPair& p, double v) { return double(p.theta) < v; };
    const auto cmp_hi = [](double v, const StarPair& p) { return v < double(p.theta); };
    const std::size_t b = std::lower_bound(pairs.begin(), pairs.end(), t - d, cmp_lo) - pairs.begin();
    const std::size_t e = std::upper_bound(pairs.begin(), pairs.end(), t + d, cmp_hi) - pairs.begin();
    const std::size_t count = e > b ? e - b : 0;
    ASSERT_EQ(s.size(), count) << "query " << q;
    if (count > 0) {
      ASSERT_EQ(s.begin, pairs.data() + b);
      ASSERT_EQ(s.end, pairs.data() + e);
    }
    if (q % 100 == 0) {
      std::size_t linear = 0;
      for (const StarPair& p : pairs) linear += (p.theta >= t - d && p.theta <= t + d);
      ASSERT_EQ(linear, count);
    }
  }
}

}  // namespace
}  // namespace st
