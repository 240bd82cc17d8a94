#include "catalog/best_fit_index.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace st {

BestFitIndex::BestFitIndex(std::vector<double> sorted, int degree) : s_(std::move(sorted)) {
  if (degree < 1 || degree > 7)
    throw std::invalid_argument("BestFitIndex: degree must be 1..7 (seed 000 eq. 10)");
  coef_.assign(std::size_t(degree) + 1, 0.0);
  const std::size_t n = s_.size();
  if (n == 0) return;
  mid_ = 0.5 * (s_.front() + s_.back());
  half_ = std::max(0.5 * (s_.back() - s_.front()), 1e-300);
  // Seed 000 eq. 8 (degree 1) and eq. 10's polynomial term: least squares of i on S(i).
  Eigen::MatrixXd a(n, degree + 1);
  Eigen::VectorXd b(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double x = (s_[i] - mid_) / half_;
    double p = 1;
    for (int j = 0; j <= degree; ++j, p *= x) a(Eigen::Index(i), j) = p;
    b(Eigen::Index(i)) = double(i);
  }
  const Eigen::VectorXd c = a.colPivHouseholderQr().solve(b);
  for (int j = 0; j <= degree; ++j) coef_[std::size_t(j)] = c(j);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t k = guess(s_[i]);
    max_error_ = std::max(max_error_, k > i ? k - i : i - k);
  }
}

double BestFitIndex::poly(double v) const {
  const double x = (v - mid_) / half_;
  double y = 0;
  for (auto it = coef_.rbegin(); it != coef_.rend(); ++it) y = y * x + *it;  // Horner
  return y;
}

std::size_t BestFitIndex::guess(double v) const {
  const double k = std::round(poly(v));  // seed 000 eq. 9: k = int[alpha cos + beta]
  if (!(k > 0)) return 0;
  return k >= double(s_.size()) ? s_.size() : std::size_t(k);
}

std::size_t BestFitIndex::first(double v, bool inclusive) const {
  // The local search about k: walk down while the value before is still in, up while the
  // value at k is still out.
  auto out = [&](std::size_t i) { return inclusive ? s_[i] < v : s_[i] <= v; };
  std::size_t k = guess(v);
  while (k > 0 && !out(k - 1)) --k;
  while (k < s_.size() && out(k)) ++k;
  return k;
}

std::pair<std::size_t, std::size_t> BestFitIndex::range(double lo, double hi) const {
  if (s_.empty() || !(lo <= hi)) return {0, 0};
  const std::size_t b = first(lo, true), e = first(hi, false);
  return b < e ? std::make_pair(b, e) : std::make_pair(b, b);
}

}  // namespace st
