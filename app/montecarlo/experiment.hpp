/// @file experiment.hpp
/// A Monte Carlo experiment of `startracker montecarlo`: a number of independent trials
/// (one random attitude each), each producing rows of the raw trial table, and a summary
/// computed from those rows alone. Because the summary only sees rows (as the strings
/// written to `<name>_trials.csv`), a run split into shards and merged gives the same report
/// as one run, byte for byte.
///
/// Determinism: trial k draws from std::mt19937_64(trialSeed(seed, k)) only, so results do
/// not depend on the thread count or on which shard runs the trial (with the same binary:
/// std::normal_distribution is implementation-defined across standard libraries).
///
/// Family: `create(name)` from the one registry table in experiment_registry.cpp.
#pragma once
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "app/montecarlo/mc_options.hpp"
#include "app/plot.hpp"

namespace st::app::mc {

using Row = std::vector<std::string>;

struct Table {
  std::vector<std::string> columns;
  std::vector<Row> rows;
  std::size_t col(const std::string& name) const;  ///< index; ProcessingError if absent
};

/// Per-trial seed: a SplitMix64 hash of (seed, trial, stream), so trials and the
/// sub-streams inside a trial (e.g. one per error situation) are independent.
uint64_t trialSeed(uint64_t seed, uint64_t trial, uint64_t stream = 0);

struct ReportTable {
  std::string name;     ///< file `<experiment>_<name>.csv`
  std::string caption;  ///< Markdown heading
  Table table;
};
struct ReportPlot {
  std::string name;  ///< file `<experiment>_<name>.png`
  Plot plot;
};
struct Report {
  std::string title;
  std::vector<std::string> notes;  ///< Markdown paragraphs after the title
  std::vector<ReportTable> tables;
  std::vector<ReportPlot> plots;
};

/// Runs trials; one per thread (owns scratch such as identifiers).
class TrialWorker {
 public:
  virtual ~TrialWorker() = default;
  /// Appends the rows of trial `trial` (first cell: the trial index) to `rows`.
  virtual void run(uint64_t trial, uint64_t seed, std::vector<Row>& rows) = 0;
};

class Experiment {
 public:
  virtual ~Experiment() = default;
  virtual std::string name() const = 0;
  /// Fills defaults (e.g. the algorithm list) and checks the options; InputError naming the
  /// option when they make no sense for this experiment.
  virtual void configure(McOptions& o) const = 0;
  /// Columns of the trial table; the first is "trial".
  virtual std::vector<std::string> columns(const McOptions& o) const = 0;
  /// Expensive set-up (database build); called once before workers are made.
  virtual void prepare(const McOptions& o) = 0;
  virtual std::unique_ptr<TrialWorker> makeWorker(const McOptions& o) const = 0;
  /// The report from all trial rows (in trial order) of the whole run.
  virtual Report summarise(const McOptions& o, const Table& trials) const = 0;
  /// Whether rows contain wall-clock measurements (then they differ between runs).
  virtual bool measuresTime() const { return false; }
  /// Whether the experiment honours McOptions::field_stop_deg / McOptions::heads (the
  /// runner refuses the option otherwise rather than ignore it).
  virtual bool usesFieldStop() const { return true; }
  virtual bool usesHeads() const { return false; }

  static std::unique_ptr<Experiment> create(const std::string& name, std::string* error = nullptr);
  static std::vector<std::string> names();
  static std::string help();  ///< "name: one line" per experiment
};

}  // namespace st::app::mc
