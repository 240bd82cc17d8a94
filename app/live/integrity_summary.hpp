/// @file integrity_summary.hpp
/// Does the run ever report a wrong attitude as valid, and how long is it without one (issue
/// 18 item 6, faults a flight tracker survives)? Printed by `replay` and `live` after the
/// navigation summary, for the steps with ground truth.
///
/// Wrong: an attitude whose error against the truth exceeds, on some body axis,
/// kSigmas x its reported 1-sigma + kFloorArcsec (the floor covers the truth's own rounding
/// and a covariance of a few arcsec that the tests' Monte Carlo check separately).
/// Valid output: the filter's estimate (every step the filter holds a state), and a fix the
/// filter took (initialised, re-initialised or accepted). A fix the filter's gate refused is
/// counted apart: the tracker said it was good, the system did not use it.
/// Outage: the longest time between consecutive frames whose fix the filter took (or, without
/// a filter, consecutive fixes) -- a fault's recovery time is the outage's end minus the
/// fault's end. Estimate outage: the same between steps with a filter estimate.
#pragma once
#include <cstdio>
#include <vector>

#include "navigation/nav_step.hpp"

namespace st::app {

struct IntegrityStats {
  static constexpr double kSigmas = 5.0, kFloorArcsec = 5.0;
  int fixes = 0;               ///< frames with a fix and truth
  int used_fixes = 0;          ///< of those, taken by the filter (or all without a filter)
  int wrong_used_fixes = 0;    ///< taken and wrong
  int wrong_refused_fixes = 0; ///< wrong but refused by the filter's gate (or ignored)
  int filter_steps = 0;        ///< steps with a filter state and truth
  int wrong_filter_steps = 0;  ///< of those, the estimate outside its bound
  double longest_outage_s = 0; ///< longest time between used fixes (from the first)
  double outage_from_s = 0, outage_to_s = 0;  ///< its ends [s from the first observation]
  double first_wrong_t = -1;   ///< [s] of the first wrong valid output (-1: none)
  /// Longest time between steps with a filter estimate (a filter suspended, e.g. by an
  /// unhealthy gyro, reports none): a gyro fault's recovery ends there.
  double longest_no_estimate_s = 0;
  double no_estimate_from_s = 0, no_estimate_to_s = 0;
};

/// The stats accumulated step by step, in fixed memory (a live run of any length).
class IntegrityAccumulator {
 public:
  void add(const NavStep& st);
  const IntegrityStats& stats() const { return s_; }

 private:
  IntegrityStats s_;
  double last_used_ = -1, last_estimate_ = -1;
};

/// "integrity: ..." lines (tests and scripts parse them).
void printIntegritySummary(const IntegrityStats& s, std::FILE* out);

}  // namespace st::app
