/// @file best_fit_index.hpp
/// Seed 000's first star-pair-ID technique (eqs. 7-10): the index i of a sorted value S(i) is
/// fitted as a polynomial of the value, k = int[p(S)], degree 1 (eq. 8's best-fit line) or
/// up to 7 (eq. 10's polynomial term: "describes data properly up to the seventh degree"),
/// and a local search about k finds the exact slice ("by varying k about the value provided
/// by equation (9)"). Kept beside the k-vector (kvector.hpp), which replaced it because it
/// needs no fit and no search: the benchmark `bench_catalog --benchmark_filter=PairIndex`
/// measures the three (and a binary search) on one database.
///
/// Least squares on the values scaled to [-1, 1] (Eigen's column-pivoted QR), not the seed's
/// CAM fit of sum |int[p] - i| (its annex is not in our copy); the search makes the answer
/// exact whatever the fit, so the fit only decides how far the search walks.
#pragma once
#include <cstddef>
#include <utility>
#include <vector>

namespace st {

class BestFitIndex {
 public:
  /// `sorted` ascending (copied: the index owns its values), polynomial `degree` 1..7.
  BestFitIndex(std::vector<double> sorted, int degree);

  /// Half-open index range [first, second) of the values in [lo, hi] (exact).
  std::pair<std::size_t, std::size_t> range(double lo, double hi) const;

  /// k = int[p(v)] clamped to [0, n] (seed 000 eq. 9): the guess before the search.
  std::size_t guess(double v) const;
  /// max |k(S(i)) - i| over the data: how far a search walks at most (seed 000 Figs. 3-6).
  std::size_t maxIndexError() const { return max_error_; }
  int degree() const { return int(coef_.size()) - 1; }

 private:
  double poly(double v) const;
  std::size_t first(double v, bool inclusive) const;  // first i with S(i) >= v (> v)
  std::vector<double> s_;
  std::vector<double> coef_;  // of x = (v - mid) / half, lowest degree first
  double mid_ = 0, half_ = 1;
  std::size_t max_error_ = 0;
};

}  // namespace st
