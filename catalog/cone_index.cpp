#include "catalog/cone_index.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "common/conventions.hpp"

namespace st {

void ConeIndex::build(const std::vector<Vec3>& u) {
  n_ = u.size();
  for (int c = 0; c < 3; ++c) {
    AxisIndex& ax = axis_[c];
    // Sorted as (coordinate, index) pairs: the same order as comparing u[a][c] then a, but
    // on contiguous keys (an indirect comparator made this a third of a database's load).
    std::vector<std::pair<double, uint32_t>> keyed(n_);
    for (std::size_t k = 0; k < n_; ++k) keyed[k] = {u[k][c], uint32_t(k)};
    std::sort(keyed.begin(), keyed.end());
    ax.order.resize(n_);
    for (std::size_t k = 0; k < n_; ++k) ax.order[k] = keyed[k].second;
    ax.u.resize(n_);
    ax.coord.resize(n_);
    for (std::size_t k = 0; k < n_; ++k) {
      ax.u[k] = u[ax.order[k]];
      ax.coord[k] = ax.u[k][c];
    }
    ax.kv.build(n_, [&](std::size_t k) { return ax.coord[k]; });
  }
}

void ConeIndex::query(const Vec3& axis, double radius, std::vector<uint32_t>& out) const {
  out.clear();
  if (n_ == 0 || !(radius >= 0)) return;
  const Vec3 w = axis.normalized();
  const double cos_r = std::cos(radius);
  if (radius >= kPi) {
    out.resize(n_);
    std::iota(out.begin(), out.end(), 0u);
    return;
  }
  // A direction within `radius` of w has, on each axis c, an angle to that axis within
  // [alpha_c - r, alpha_c + r] (alpha_c = acos w_c), i.e. its coordinate lies in a slab
  // found by the k-vector on that coordinate. Take the thinnest of the three slabs.
  std::pair<std::size_t, std::size_t> best{0, n_};
  int best_c = 0;
  for (int c = 0; c < 3; ++c) {
    const double alpha = std::acos(std::clamp(w[c], -1.0, 1.0));
    const double lo = std::cos(std::min(kPi, alpha + radius)) - 1e-12;
    const double hi = std::cos(std::max(0.0, alpha - radius)) + 1e-12;
    const auto r = axis_[c].kv.range(lo, hi, [&](std::size_t k) { return axis_[c].coord[k]; });
    if (r.second - r.first < best.second - best.first) {
      best = r;
      best_c = c;
    }
  }
  const AxisIndex& ax = axis_[best_c];
  for (std::size_t k = best.first; k < best.second; ++k)
    if (ax.u[k].dot(w) >= cos_r) out.push_back(ax.order[k]);
  std::sort(out.begin(), out.end());
}

}  // namespace st
