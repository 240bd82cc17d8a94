/// @file solve_run.hpp
/// One frame of `solve` (solve_run.cpp) and what the frames of a run share; the run itself,
/// one frame or a batch, is solve_batch.cpp.
#pragma once
#include <memory>
#include <optional>
#include <string>

#include "app/solve/celestial_frame.hpp"
#include "app/solve/database_cache.hpp"
#include "app/solve/frame_input.hpp"
#include "app/solve/solve_options.hpp"
#include "app/solve/solve_output.hpp"

namespace st::app {

/// Loaded once per run: the --database file, or the cache of in-memory databases.
struct SolveSources {
  explicit SolveSources(const SolveOptions& o);
  std::optional<StarDatabase> file_db;
  double file_db_ms = 0;
  DatabaseCache cache;
  CelestialFrame frame;  ///< the frame asked for
};

/// A frame's result, kept until it is printed (a batch prints in input order).
struct FrameOutcome {
  SolveOptions o;  ///< the run's options, input = this frame
  FrameInput in;
  std::shared_ptr<const StarDatabase> db;  ///< keeps a cached database alive
  std::unique_ptr<SolveReport> rep;        ///< null when an error ended the frame
  int code = 0;                            ///< 0 solved, 1 not solved, 2 bad input
  std::string error;                       ///< the error that ended the frame
  double ms = 0;                           ///< wall time of the frame
};

/// Loads, detects, identifies o.input. Throws InputError / std::exception on an error (the
/// batch catches them per frame).
std::unique_ptr<FrameOutcome> solveFrame(const SolveOptions& o, SolveSources& src);

/// Prints the frame (text, or one JSON line) and writes --annotate / --wcs; returns its code.
int reportFrame(FrameOutcome& f);

}  // namespace st::app
