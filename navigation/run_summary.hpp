/// @file run_summary.hpp
/// The summary of a navigator run against GROUND_TRUTH, printed by `replay` and `live` alike:
/// attitude errors (cross-boresight, roll, filter vs raw fixes), NEES of the filter and of the
/// raw fixes, identification errors. Prints nothing without truth. A run without a filter (no
/// step holds a filter state: no gyro) is scored on its raw fixes, with no filter NEES.
#pragma once
#include <cstdio>
#include <vector>

#include "navigation/nav_step.hpp"

namespace st {

void printNavigationSummary(const std::vector<NavStep>& steps, std::FILE* out);
/// The body-rate lines: the filter's rate error against the truth's (fillTruthRates first),
/// RMS per axis and total, the rate NEES of a gyroless filter, and the tracker's own
/// frame-to-frame rates. Prints nothing without true rates.
void printRateSummary(const std::vector<NavStep>& steps, std::FILE* out);

}  // namespace st
