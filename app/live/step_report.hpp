/// @file step_report.hpp
/// What replay and live report of a run's steps, made as the steps finish so that neither
/// keeps them (an hour at 10 Hz is 36,000 steps of ~1 KB): the true rate of each step
/// (TruthRateStream), the run summary (RunSummary), the integrity counts
/// (IntegrityAccumulator) and the CSV (NavStepCsvWriter). One class, so both print the same.
/// Not thread-safe (LiveNavigator serialises calls).
#pragma once
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "app/live/integrity_summary.hpp"
#include "navigation/nav_step.hpp"
#include "navigation/run_summary.hpp"

namespace st::app {

class StepReport {
 public:
  /// The frame steps counted as they come (replay's "frames:" line).
  struct Counts {
    int frames = 0, solved = 0, lost_in_space = 0, tracking = 0, rejected = 0;
    int reacquired = 0;  ///< lost-in-space in the frame whose windows failed
    double frame_time_s = 0;  ///< [s] the pipeline's time over all frames
  };
  /// `csv_path`: the steps' CSV (empty: none). `keep`: also keep the final steps (plots).
  explicit StepReport(const std::string& csv_path = "", bool keep = false);
  /// A finished step (in order).
  void push(const NavStep& s);
  /// The end of the run: releases the steps held for their true rate.
  void flush();
  /// The summary, rate and integrity lines.
  void print(std::FILE* out) const;
  /// Closes the CSV; returns its rows (-1 without one).
  int finishCsv();
  /// The final steps, when kept.
  const std::vector<NavStep>& steps() const { return kept_; }
  const Counts& counts() const { return counts_; }

 private:
  void final(const NavStep& s);

  TruthRateStream truth_rates_;  // holds a step until its true rate is known
  RunSummary summary_;
  IntegrityAccumulator integrity_;
  std::unique_ptr<NavStepCsvWriter> csv_;
  bool keep_ = false;
  std::vector<NavStep> kept_;
  Counts counts_;
};

}  // namespace st::app
