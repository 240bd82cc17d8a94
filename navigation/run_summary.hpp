/// @file run_summary.hpp
/// The summary of a navigator run against GROUND_TRUTH, printed by `replay` and `live` alike:
/// attitude errors (cross-boresight, roll, filter vs raw fixes), NEES of the filter and of the
/// raw fixes, identification errors. Prints nothing without truth. A run without a filter (no
/// step holds a filter state: no gyro) is scored on its raw fixes, with no filter NEES.
///
/// Accumulated step by step in fixed memory (RMS, max and chi-square fractions exact;
/// percentiles from a 1 % log histogram, common/log_histogram.hpp), so that a live run of any
/// length keeps no per-step record for it.
#pragma once
#include <cstdio>
#include <string>
#include <vector>

#include "common/log_histogram.hpp"
#include "navigation/nav_step.hpp"

namespace st {

class RunSummary {
 public:
  void add(const NavStep& s);
  void print(std::FILE* out) const;
  /// The body-rate lines (steps with a true rate: through TruthRateStream first):
  /// the filter's rate error per axis and total, the rate NEES of a gyroless filter, and the
  /// tracker's own frame-to-frame rates. Prints nothing without true rates.
  void printRates(std::FILE* out) const;

 private:
  /// One error or NEES series: exact count, RMS, mean, max; quantiles to 0.5 %.
  struct Series {
    LogHistogram h;
    double sum = 0, sum_sq = 0;
    uint64_t below_q50 = 0, below_q95 = 0;  // NEES: values <= the chi2(3) median / 95 % point
    void add(double v);
    uint64_t n() const { return h.count(); }
    bool empty() const { return n() == 0; }
    double rms() const;
    double mean() const;
  };
  /// The same run scored two ways until the end says whether a filter ran: its estimates
  /// (filtered) or the raw fixes (no step held a filter state).
  struct Scored {
    Series cross, roll, fix_err, fix_nees;
  };
  bool filtered_ = false;
  Scored filt_, raw_;
  Series nees_, filt_err_, unfiltered_err_;
  long matched_with_truth_ = 0, misidentified_ = 0, blend_claims_ = 0, unscored_ = 0;

  void addRate(const NavStep& s);
  bool gyroless_ = false;

  /// Several heads: each head's own fixes in its own frame (roll about its own boresight),
  /// and the joint fixes in the body frame.
  struct HeadSeries {
    std::string label;
    uint64_t frames = 0, solved = 0;
    long misidentified = 0;
    Series cross, roll, total;
  };
  void addHeads(const NavStep& s);
  void printHeads(std::FILE* out) const;
  std::vector<HeadSeries> heads_;
  uint64_t head_steps_ = 0, merged_ = 0, disagreed_ = 0;
  Series joint_cross_, joint_roll_, joint_total_, heads_chi2_;
  Series rate_x_, rate_y_, rate_z_, rate_total_, rate_nees_, rate_fix_err_;  // [deg/s], NEES
};

}  // namespace st
