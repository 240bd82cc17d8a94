/// @file star_selection.hpp
/// Selecting the on-board catalog (seed 004 "Reduced catalog" and "Double star reduction"):
/// double-star merge and the uniform-density reduction. Work on positions already corrected
/// to the observation epoch.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/attitude.hpp"

namespace st {

struct SelectedStar {
  uint32_t id;  ///< catalog id (the brightest member for a merged group)
  Vec3 u;       ///< unit vector
  double mag;   ///< V
};

/// Combined magnitude of two stars, seed 004 eq. 6.1 (with base 10: the paper prints e, but
/// magnitudes are defined by 10^(-0.4 m); two equal stars give m - 0.753).
double combinedMagnitude(double m1, double m2);

/// Merges stars closer than `sep` [rad] (transitively: a chain of close stars is one group)
/// into one star with the combined magnitude (eq. 6.1 over all members) and the
/// intensity-weighted direction (eq. 6.2, normalised). Returns the merged list (order not
/// specified); `groups` and `absorbed` count the merged groups and the stars that vanished.
std::vector<SelectedStar> mergeDoubleStars(const std::vector<SelectedStar>& in, double sep,
                                           std::size_t* groups = nullptr,
                                           std::size_t* absorbed = nullptr);

}  // namespace st
