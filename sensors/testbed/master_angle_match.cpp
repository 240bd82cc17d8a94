#include "sensors/testbed/master_angle_match.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace st::testbed {
AngleDatabase::AngleDatabase(std::vector<Vec3> stars) : stars_(std::move(stars)) {
  for (int i = 0; i < static_cast<int>(stars_.size()); ++i)
    for (int j = i + 1; j < static_cast<int>(stars_.size()); ++j)
      pairs_.push_back({angleBetween(stars_[i], stars_[j]), i, j});  // seed 001 eq. 1
  std::sort(pairs_.begin(), pairs_.end(),
            [](const Pair& a, const Pair& b) { return a.angle < b.angle; });
}

std::vector<AngleDatabase::Pair> AngleDatabase::lookup(double angle, double tol) const {
  auto lo = std::lower_bound(pairs_.begin(), pairs_.end(), angle - tol,
                             [](const Pair& p, double a) { return p.angle < a; });
  std::vector<Pair> out;
  for (; lo != pairs_.end() && lo->angle <= angle + tol; ++lo) out.push_back(*lo);
  return out;
}

MasterAngleMatch matchMasterAngles(const std::vector<Vec3>& obs, const AngleDatabase& db,
                                   double tol) {
  MasterAngleMatch m;
  if (obs.size() < 2) {
    m.reason = "fewer than 2 stars observed";
    return m;
  }
  std::vector<std::pair<int, AngleDatabase::Pair>> unique;  // (observation, its one pair)
  for (int k = 1; k < static_cast<int>(obs.size()); ++k) {
    const auto found = db.lookup(angleBetween(obs[0], obs[k]), tol);
    if (found.size() == 1) unique.push_back({k, found[0]});
    m.angles_ambiguous += found.size() > 1;  // multiple matches filtered out (sec. V.A)
  }
  m.angles_unique = static_cast<int>(unique.size());
  // The master is the star common to the matched pairs: each pair votes for both its stars.
  std::map<int, int> votes;
  for (const auto& [k, p] : unique) {
    ++votes[p.i];
    ++votes[p.j];
  }
  int best = -1, best_votes = 0, ties = 0;
  for (const auto& [star, v] : votes) {
    if (v > best_votes) {
      best = star;
      best_votes = v;
      ties = 0;
    } else if (v == best_votes) {
      ++ties;
    }
  }
  if (best_votes < 2 || ties > 0) {
    m.reason = best_votes < 2 ? "fewer than 2 master angles matched one database pair"
                              : "master star ambiguous";
    return m;
  }
  m.master_star = best;
  m.stars.push_back({0, best});
  std::map<int, int> used;  // database star -> how many observations claim it
  std::vector<std::pair<int, int>> others;
  for (const auto& [k, p] : unique) {
    if (p.i != best && p.j != best) continue;  // a pair without the master: inconsistent
    const int star = p.i == best ? p.j : p.i;
    others.push_back({k, star});
    ++used[star];
  }
  for (const auto& o : others)
    if (used[o.second] == 1) m.stars.push_back(o);  // a star claimed twice is dropped
  return m;
}

}  // namespace st::testbed
