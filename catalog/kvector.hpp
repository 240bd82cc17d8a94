/// @file kvector.hpp
/// Mortari's k-vector (seed 000, eqs. 11-14): an integer index over a sorted array that turns
/// a range query [lo, hi] into two table look-ups with no binary search. The line
/// z(j) = q + m * j joins the first and last sorted values (widened by a tiny xi so both ends
/// are strictly inside); K(j) = number of values <= z(j). A query reads K at
/// j_bot = floor((lo - q) / m) and j_top = ceil((hi - q) / m); the candidate slice
/// [K(j_bot), K(j_top)) holds every match plus at most the values of two line steps at the
/// ends, which are trimmed, so the cost is O(1 + matches) and the answer is exact.
#pragma once
#include <cmath>
#include <cstddef>
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "common/huge_page_allocator.hpp"

namespace st {

class KVector {
 public:
  KVector() = default;
  /// `sorted[i]` ascending, read through `value(i)`; `bins` line steps (Mortari uses n).
  template <class ValueAt>
  void build(std::size_t n, ValueAt value, std::size_t bins = 0);

  /// Half-open index range [first, second) of the sorted values in [lo, hi] (exact).
  template <class ValueAt>
  std::pair<std::size_t, std::size_t> range(double lo, double hi, ValueAt value) const;

  std::size_t size() const { return k_.size(); }
  double slope() const { return m_; }
  double intercept() const { return q_; }
  const std::vector<uint32_t, HugePageAllocator<uint32_t>>& table() const { return k_; }

 private:
  /// K(j): number of values <= q + m j (the pairs' table is MBs: huge pages, see allocator)
  std::vector<uint32_t, HugePageAllocator<uint32_t>> k_;
  double m_ = 1, q_ = 0;
  std::size_t n_ = 0;
};

template <class ValueAt>
void KVector::build(std::size_t n, ValueAt value, std::size_t bins) {
  n_ = n;
  k_.clear();
  if (n == 0) return;
  if (bins < 2) bins = n < 2 ? 2 : n;
  const double y0 = value(0), y1 = value(n - 1);
  // seed 000 eq. 11, with xi widening so the line starts below y0 and ends above y1.
  const double xi = 1e-9 * std::max({std::fabs(y0), std::fabs(y1), 1e-300}) + 1e-12 * (y1 - y0);
  m_ = (y1 - y0 + 2 * xi) / double(bins - 1);
  if (!(m_ > 0)) m_ = 1e-300 + 2 * xi;
  q_ = y0 - xi;
  k_.resize(bins);
  std::size_t i = 0;
  for (std::size_t j = 0; j < bins; ++j) {  // seed 000 eq. 12
    const double z = q_ + m_ * double(j);
    while (i < n && value(i) <= z) ++i;
    k_[j] = uint32_t(i);
  }
}

template <class ValueAt>
std::pair<std::size_t, std::size_t> KVector::range(double lo, double hi, ValueAt value) const {
  if (n_ == 0 || !(lo <= hi)) return {0, 0};
  const long last = long(k_.size()) - 1;
  // seed 000 eq. 13 (one extra step each side against rounding of the division)
  const double fb = std::floor((lo - q_) / m_) - 1, ft = std::ceil((hi - q_) / m_) + 1;
  std::size_t begin, end;
  if (fb < 0)
    begin = 0;
  else if (fb > double(last))
    return {n_, n_};
  else
    begin = k_[std::size_t(fb)];  // eq. 14: k_start = K(l_bot) (+1 in 1-based indexing)
  if (ft < 0)
    return {0, 0};
  else if (ft >= double(last))
    end = n_;
  else
    end = k_[std::size_t(ft)];  // eq. 14: k_end = K(l_top)
  while (begin < end && value(begin) < lo) ++begin;  // trim the partial line steps
  while (end > begin && value(end - 1) > hi) --end;
  return {begin, end};
}

}  // namespace st
