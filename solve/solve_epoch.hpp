/// @file solve_epoch.hpp
/// Which epoch `solve` identifies at, and whether a star database file can serve it. A
/// database holds apparent directions at its own epoch (proper motion, parallax, annual
/// aberration applied when it was built) but no proper motions, so it cannot be moved to
/// another epoch: it is refused when the stars would move by more than
/// kEpochToleranceArcsec between the two epochs.
#pragma once
#include <optional>
#include <string>

#include "catalog/star_database.hpp"

namespace st::solve {

/// Largest star shift a database may be used with [arcsec]: well below a pixel of any
/// camera this project solves (>= 5 arcsec/px) and below the 1-sigma of a solve.
constexpr double kEpochToleranceArcsec = 1.0;
/// Bound on any star's proper motion [arcsec/yr]: Barnard's star, the fastest in Hipparcos.
constexpr double kMaxProperMotionArcsecPerYear = 10.4;
/// Bound on any star's parallax [arcsec]: Proxima Centauri.
constexpr double kMaxParallaxArcsec = 0.77;

struct SolveEpoch {
  double jyear = 0;
  std::string source;  ///< "--epoch", "DATE-OBS", "file name", "database" or "today"
};

/// --epoch when given (> 0), else the frame's own epoch, else the database file's (an
/// undated frame is taken at the epoch the user built the database for), else today.
SolveEpoch chooseEpoch(double cli_epoch, const std::optional<double>& frame_epoch,
                       const std::string& frame_source, const StarDatabase* db_file);

/// Upper bound [arcsec] of how far a star of database `p` moves between p.epoch_jyear and
/// `epoch_jyear`: proper motion (kMaxProperMotionArcsecPerYear) plus the change of annual
/// aberration and parallax (the Earth's velocity and position at both epochs) when the
/// database applied them.
double epochShiftBoundArcsec(const DatabaseParams& p, double epoch_jyear);

/// InputError naming both epochs, the shift and how to rebuild, when the bound exceeds
/// kEpochToleranceArcsec.
void requireDatabaseEpoch(const StarDatabase& db, const std::string& path, const SolveEpoch& e);

}  // namespace st::solve
