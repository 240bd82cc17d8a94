#include "sensors/testbed/near_field_solver.hpp"

#include <cmath>

#include "common/errors.hpp"

namespace st::testbed {

bool NearFieldOptions::isValid(std::string* why) const {
  std::string p, err;
  if (!(tolerance > 0) || !std::isfinite(tolerance)) {
    p = "tolerance must be > 0";
  } else if (iterations < 1) {
    p = "iterations must be >= 1";
  } else if (!(sigma > 0) || !std::isfinite(sigma)) {
    p = "sigma must be > 0";
  } else if (min_stars < 2) {
    p = "min_stars must be >= 2";
  } else if (!WahbaSolver::create(solver, &err)) {
    p = "solver: " + err;
  }
  if (why) *why = p;
  return p.empty();
}

bool NearFieldResult::ok() const { return !passes.empty() && passes.back().ok; }

Quat NearFieldResult::q_ib() const {
  return passes.empty() ? Quat::Identity() : passes.back().q_ib;
}

NearFieldSolver::NearFieldSolver(const DisplayGeometry& geometry, std::vector<Vec3> stars,
                                 const NearFieldOptions& options)
    : geometry_(geometry), db_(std::move(stars)), options_(options) {
  std::string why;
  if (!geometry_.isValid(&why)) throw InputError("testbed geometry: " + why);
  if (!options_.isValid(&why)) throw InputError("near-field options: " + why);
  solver_ = WahbaSolver::create(options_.solver);
}

std::vector<std::optional<Vec3>> NearFieldSolver::nearFieldVectors(
    const std::vector<Vec3>& b_cam, const Quat& q_pred) const {
  std::vector<std::optional<Vec3>> w;
  w.reserve(b_cam.size());
  for (const Vec3& b : b_cam) w.push_back(geometry_.nearFieldVector(b, q_pred));
  return w;
}

NearFieldPass NearFieldSolver::pass(const std::vector<Vec3>& b_cam, const Quat& q_pred) const {
  NearFieldPass p;
  p.q_ib = q_pred;
  // Near-field vectors from the prediction (seed 001 sec. IV.B); a ray that misses the screen
  // at the predicted attitude cannot be corrected and is left out.
  std::vector<Vec3> w;
  std::vector<int> index;  // w[k] is observation index[k]
  const auto all = nearFieldVectors(b_cam, q_pred);
  for (std::size_t k = 0; k < all.size(); ++k)
    if (all[k]) {
      w.push_back(*all[k]);
      index.push_back(static_cast<int>(k));
    }
  const MasterAngleMatch m = matchMasterAngles(w, db_, options_.tolerance);
  p.angles_unique = m.angles_unique;
  p.angles_ambiguous = m.angles_ambiguous;
  if (m.master_star < 0) {
    p.reason = m.reason;
    return p;
  }
  p.stars_matched = static_cast<int>(m.stars.size());
  std::vector<VectorObservation> obs;
  for (const auto& [k, star] : m.stars) {
    p.matches.push_back({index[k], star});
    obs.push_back({w[k], db_.stars()[star], options_.sigma});  // w = A r (eq. 54 / beta)
  }
  if (p.stars_matched < options_.min_stars) {
    p.reason = std::to_string(p.stars_matched) + " stars matched, need " +
               std::to_string(options_.min_stars);
    return p;
  }
  const WahbaSolution sol = solver_->solve(obs);
  if (!sol.ok) {
    p.reason = sol.reason;
    return p;
  }
  p.ok = true;
  p.q_ib = sol.q_ib;
  p.cov_body = sol.cov_body;
  return p;
}

NearFieldResult NearFieldSolver::solve(const std::vector<Vec3>& b_cam, const Quat& q_pred) const {
  NearFieldResult r;
  Quat q = q_pred;
  for (int it = 0; it < options_.iterations; ++it) {
    r.passes.push_back(pass(b_cam, q));
    q = r.passes.back().q_ib;  // the estimate is the next prediction (sec. IV.B)
  }
  return r;
}

std::vector<Vec3> displayDatabase(const DisplayGeometry& g, const std::vector<Vec2>& px) {
  std::vector<Vec3> r;
  r.reserve(px.size());
  for (const Vec2& p : px) r.push_back(DisplayGeometry::databaseVector(g.screenPoint(p)));
  return r;
}

}  // namespace st::testbed
