/// @file runner.hpp
/// Runs an experiment's trials (threads, shards, progress bar), writes the trial table and
/// the run description, and, for a whole run, the report: Markdown + one CSV per table +
/// PNG plots. `mergeRuns` rebuilds the same report from shard files.
///
/// Files in the output directory for experiment E:
///   E_trials.csv, E_run.txt            (unsharded or merged run)
///   E_trials.shard-i-of-N.csv, E_run.shard-i-of-N.txt   (one shard; no report)
///   E.md, E_<table>.csv, E_<plot>.png (+ E_<plot>.gp, the gnuplot script)
#pragma once
#include <string>
#include <vector>

#include "app/montecarlo/mc_options.hpp"

namespace st::app::mc {

/// Runs `o.experiment`; returns the CLI exit code (1 when plotting failed, after the
/// tables were written). InputError on bad options.
int runExperiment(McOptions o);

/// Merges the run files found in `dirs` (every experiment found, each from a complete set of
/// shards of one run) into `o.out_dir`; `o` supplies only the run options (out_dir, plots,
/// gnuplot, progress). InputError naming the file on incomplete or inconsistent shards.
int mergeRuns(const std::vector<std::string>& dirs, const McOptions& o);

}  // namespace st::app::mc
