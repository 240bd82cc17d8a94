/// @file master_angle_match.hpp
/// The angle method as the seed's testbed ran it (seed 001 sec. II.A eq. 1 and sec. V): the
/// angles between the brightest ("master") observed star and every other observed star are
/// looked up among all the database's pair angles within +-tolerance; an angle that fits
/// more than one database pair is dropped ("all the multiple matches were filtered out");
/// the master's identity is the database star common to most of the remaining pairs, and
/// each other star is the master's partner in its pair.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "common/attitude.hpp"

namespace st::testbed {

/// Every pair angle of a small database (the display's stars), sorted for range look-ups.
class AngleDatabase {
 public:
  /// `stars`: unit vectors in frame I; the index is the star number.
  explicit AngleDatabase(std::vector<Vec3> stars);
  const std::vector<Vec3>& stars() const { return stars_; }
  struct Pair {
    double angle;  ///< [rad]
    int i, j;      ///< star numbers, i < j
  };
  /// The pairs whose angle lies in [angle - tol, angle + tol].
  std::vector<Pair> lookup(double angle, double tol) const;

 private:
  std::vector<Vec3> stars_;
  std::vector<Pair> pairs_;  // sorted by angle
};

struct MasterAngleMatch {
  int master_star = -1;                    ///< database star of observation 0; -1 = none
  std::vector<std::pair<int, int>> stars;  ///< (observation, database star), master first
  int angles_unique = 0;     ///< master angles that fit exactly one database pair
  int angles_ambiguous = 0;  ///< fitted several pairs: filtered out
  std::string reason;        ///< why no master was identified (empty when it was)
};

/// `obs`: unit vectors, brightest first (observation 0 is the master). tol [rad] is the
/// half-width of the window (the seed's 500" "matching accuracy" is tol = 250").
MasterAngleMatch matchMasterAngles(const std::vector<Vec3>& obs, const AngleDatabase& db,
                                   double tol);

}  // namespace st::testbed
