/// @file drop_worst.hpp
/// "Solve, drop the worst, re-solve", written once. Tracking (the residual chi-square of the
/// pixel refinement) and lost-in-space verification (the seeds' gate and the residual
/// chi-square of a match set, sensors/identify/verify.cpp) all remove outliers this way: judge
/// the current solution; while it fails and more than a minimum of observations remain, drop
/// the one with the largest normalised residual and solve again without it.
///
/// A function template (header only): it runs per tracking frame, and the callers' closures
/// must inline.
#pragma once
#include <cstddef>

namespace st {

/// What `judge` says of the current solution: acceptable, or which observation is worst.
struct DropWorstVerdict {
  bool pass = false;
  std::size_t worst = 0;  ///< index of the observation to drop when !pass
};

enum class DropWorstOutcome {
  kAccepted,      ///< the judge passed a solution
  kTooFew,        ///< it still failed with min_count observations left
  kSolverFailed,  ///< drop_and_resolve could not solve (or gave up)
};

/// Starts from a solution of `count` observations. `judge()` -> DropWorstVerdict;
/// `drop_and_resolve(worst)` removes that observation, solves again and returns false when
/// that failed. Never drops below `min_count`.
template <class Judge, class DropAndResolve>
DropWorstOutcome dropWorstWhileFailing(std::size_t count, std::size_t min_count, Judge&& judge,
                                       DropAndResolve&& drop_and_resolve) {
  for (;;) {
    const DropWorstVerdict v = judge();
    if (v.pass) return DropWorstOutcome::kAccepted;
    if (count <= min_count) return DropWorstOutcome::kTooFew;
    if (!drop_and_resolve(v.worst)) return DropWorstOutcome::kSolverFailed;
    --count;
  }
}

}  // namespace st
