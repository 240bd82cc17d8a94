/// @file catalog_fixture.hpp
/// Shared, lazily built databases for the catalog tests (built once per test program).
#pragma once
#include <algorithm>
#include <random>
#include <utility>
#include <vector>

#include "catalog/star_database.hpp"

namespace st::test {

/// The committed Hipparcos subset (loaded once).
const StarCatalog& hipSubset();
/// Parameters of the reference database: 15 deg pairs, V <= 6.5, epoch 2020.0, 10 arcsec
/// double-star merge, neighbours within 5 deg.
DatabaseParams params15();
/// The reference database built from hipSubset() with params15().
const StarDatabase& hipDatabase15();

/// `n` sorted values clustered in two Gaussians, with a run of duplicates every 50: what
/// stresses a range index (a k-vector's line, a best-fit polynomial) most.
inline std::vector<double> clusteredSortedValues(std::size_t n, std::mt19937_64& rng) {
  std::vector<double> y(n);
  std::normal_distribution<double> g1(0.2, 0.01), g2(0.8, 0.2);
  for (std::size_t i = 0; i < n; ++i) y[i] = (i % 3 == 0) ? g1(rng) : g2(rng);
  for (std::size_t i = 1; i < n; i += 50) y[i] = y[i - 1];
  std::sort(y.begin(), y.end());
  return y;
}

/// The exact half-open range of the sorted `y` in [lo, hi] (binary search): the reference.
inline std::pair<std::size_t, std::size_t> bruteRange(const std::vector<double>& y, double lo,
                                                      double hi) {
  return {std::size_t(std::lower_bound(y.begin(), y.end(), lo) - y.begin()),
          std::size_t(std::upper_bound(y.begin(), y.end(), hi) - y.begin())};
}

}  // namespace st::test
