/// @file log_histogram.hpp
/// Quantiles of a long stream of positive values in fixed memory: counts in bins 1 % wide on
/// a log scale from kLo to kHi (values outside go to the end bins; the exact min and max are
/// kept and bound every answer). A quantile is exact to the bin: within 0.5 % of the value.
/// For summaries of runs of unbounded length (a live star tracker), where keeping every
/// value would grow without end.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace st {

class LogHistogram {
 public:
  static constexpr double kLo = 1e-6, kHi = 1e8, kRatio = 1.01;

  LogHistogram() : counts_(bins(), 0) {}

  void add(double v) {
    if (!std::isfinite(v)) return;
    v = std::max(v, 0.0);
    min_ = std::min(min_, v);
    max_ = std::max(max_, v);
    ++counts_[binOf(v)];
    ++n_;
  }
  uint64_t count() const { return n_; }
  double min() const { return n_ ? min_ : 0.0; }
  double max() const { return n_ ? max_ : 0.0; }
  /// The value below which a fraction p of the values lie (the geometric centre of its bin,
  /// clamped to [min, max]; the min or max in an end bin); 0 when empty.
  double quantile(double p) const {
    if (n_ == 0) return 0;
    const uint64_t rank = std::max<uint64_t>(1, uint64_t(std::ceil(p * double(n_))));
    uint64_t seen = 0;
    for (std::size_t b = 0; b < counts_.size(); ++b) {
      seen += counts_[b];
      if (seen < rank) continue;
      // The end bins hold everything beyond the range: bounded by the exact min and max.
      if (b == 0) return min();
      if (b + 1 == counts_.size()) return max();
      return std::clamp(centre(b), min(), max());
    }
    return max();
  }

 private:
  static std::size_t bins() {
    return std::size_t(std::ceil(std::log(kHi / kLo) / std::log(kRatio))) + 1;
  }
  std::size_t binOf(double v) const {
    if (v <= kLo) return 0;
    const double b = std::floor(std::log(v / kLo) / std::log(kRatio));
    return std::min(counts_.size() - 1, std::size_t(b));
  }
  static double centre(std::size_t b) { return kLo * std::pow(kRatio, double(b) + 0.5); }

  std::vector<uint64_t> counts_;
  uint64_t n_ = 0;
  double min_ = std::numeric_limits<double>::infinity(), max_ = 0;
};

}  // namespace st
