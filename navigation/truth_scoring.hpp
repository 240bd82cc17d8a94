/// @file truth_scoring.hpp
/// Scoring of a navigator step against a GROUND_TRUTH observation of a simulated run: the
/// filter's and the raw fix's attitude errors and NEES, and the identities of the matched
/// stars against the truth's star list. Evaluation only: the estimator never sees the truth.
#pragma once
#include <mrpt/obs/CObservation6DFeatures.h>

#include "fusion/fusion_loop.hpp"
#include "navigation/nav_step.hpp"
#include "sensors/mrpt/observation_star_tracker.hpp"

namespace st {

/// Fills the truth fields of `s`; `fixes` are the step's star-tracker observations, one per
/// head in the order of s.heads (none when the step has no frame): their matched stars are
/// checked against the truth's stars of the same head. With several heads each head's own
/// fix is scored too (NavHead::fix_error, misidentified).
void scoreTruth(NavStep& s, const mrpt::obs::CObservation6DFeatures& truth,
                const std::vector<CObservationStarTracker::Ptr>& fixes);

}  // namespace st
