#include "sensors/identify/verify_refine.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "common/chi_square.hpp"
#include "common/conventions.hpp"

namespace st {

namespace {
void sortByObservation(std::vector<StarMatch>& matches) {
  std::sort(matches.begin(), matches.end(),
            [](const StarMatch& a, const StarMatch& b) { return a.obs_index < b.obs_index; });
}

bool samePairs(const std::vector<StarMatch>& a, const std::vector<StarMatch>& b) {
  return a.size() == b.size() &&
         std::equal(a.begin(), a.end(), b.begin(), [](const StarMatch& x, const StarMatch& y) {
           return x.obs_index == y.obs_index && x.star_index == y.star_index;
         });
}
}  // namespace

VerifyRefinement::VerifyRefinement(const VerifierParts& parts,
                                   const std::vector<StarObservation>& obs, Quat q_ic,
                                   Mat3 cov_cam)
    : p_(parts),
      opt_(parts.options),
      obs_(obs),
      stars_(parts.db.stars()),
      n_obs_(static_cast<int>(obs.size())),
      min_gate_(parts.options.min_gate_px * parts.camera.pixelScale()),
      residual_test_(opt_.enabled && opt_.residual_test && opt_.scale_tolerance <= 0),
      near_test_(opt_.enabled && opt_.near_miss_test && opt_.scale_tolerance <= 0),
      best_pred_(n_obs_),
      gate_cos_(n_obs_),
      gate_rad_(n_obs_),
      best_dot_(n_obs_),
      excluded_(n_obs_, 0),
      ambiguous_(n_obs_, 0),
      forced_(n_obs_, -1) {
  sol_.ok = true;
  sol_.q_ib = q_ic;  // WahbaSolution is frame-agnostic: here the camera's attitude
  sol_.cov_body = cov_cam;
}

VerificationResult VerifyRefinement::run(double attitudes_examined, int free_matches) {
  iterate();
  res_.q_ic = canonical(sol_.q_ib);
  res_.cov_cam = sol_.cov_body;
  measureResiduals();
  res_.matches = matches_;
  res_.false_match_probability = falseMatchProbability(attitudes_examined, free_matches);
  // Near misses left after the refits (model in verify.hpp).
  double near_tail = 1.0;
  if (near_test_ && !matches_.empty()) {
    res_.near_misses = findNearMisses();
    near_tail = binomialUpperTail(n_unmatched_, res_.near_misses, near_p_);
  }
  decide(near_tail);
  return res_;
}

// Rounds of match / re-solve, outlier exclusion and near-miss fitting until the match set
// stops changing; each re-solve counts against the guard.
void VerifyRefinement::iterate() {
  bool rematch = true;
  guard_limit_ = 3 * n_obs_ + 10;
  for (guard_ = 0; guard_ < guard_limit_ && !settled_; ++guard_) {
    const bool fresh = rematch;
    rematch = false;
    if (fresh) refitUntilStable();
    if (matches_.size() < 2) break;
    int dropped = 0;
    if (!passesResidualTest(dropped)) {
      residual_failed_ = true;
      break;
    }
    // The set was edited (outliers out, near misses in): match again at the new attitude.
    if (dropped > 0 || !fresh) {
      rematch = true;
      continue;
    }
    if (near_test_ && absorbNearMisses()) continue;
    settled_ = true;
  }
  if (!settled_ && !residual_failed_ && matches_.size() >= 2 && residual_test_)
    residual_failed_ = true;  // never settled: do not trust it
}

void VerifyRefinement::refitUntilStable() {
  std::vector<StarMatch> prev;
  for (int iter = 0; iter < std::max(1, opt_.refine_iterations); ++iter) {
    match();
    if (matches_.size() < 2) break;
    const WahbaSolution next = solveMatches({});
    if (!next.ok) break;
    sol_ = next;
    if (samePairs(prev, matches_)) break;
    prev = matches_;
  }
}

// Mutual nearest neighbours inside the gates at the attitude sol_ (excluded observations
// take no part); fills pred_, best_pred_, best_obs_, gate_rad_/cos_ and matches_.
void VerifyRefinement::match() {
  predictInField();
  nearestAndGates();
  keepUnambiguous();
  keepForced();
  res_.predicted_in_fov = static_cast<int>(pred_.size());
}

void VerifyRefinement::predictInField() {
  const Mat3 R_ic = sol_.q_ib.toRotationMatrix();
  const Mat3 R_ci = R_ic.transpose();
  const Mat3 p = sol_.cov_body;
  cone_.clear();
  p_.db.coneQuery(R_ic.col(2), p_.cone_radius, cone_);
  pred_.clear();
  for (uint32_t s : cone_) {
    const Vec3 v_c = R_ci * stars_[s].u_i;
    if (v_c.z() <= 0 || !p_.camera.isVectorInImage(v_c, opt_.edge_margin_px)) continue;
    // Direction error from a camera-frame rotation error dtheta is dtheta x v_c (eq. of
    // the linearised rotation); its per-axis variance is (tr P - v^T P v) / 2.
    const double var_att = std::max(0.0, (p.trace() - v_c.dot(p * v_c)) / 2.0);
    pred_.push_back({s, v_c, var_att});
  }
}

// Nearest predicted star of every observation (and nearest non-excluded observation of
// every predicted star), and the observation's gate.
void VerifyRefinement::nearestAndGates() {
  const int n_pred = static_cast<int>(pred_.size());
  best_obs_.assign(n_pred, -1);
  std::vector<double> best_obs_dot(n_pred, -2.0);
  for (int k = 0; k < n_obs_; ++k) {
    best_pred_[k] = -1;
    best_dot_[k] = -2.0;
    const Vec3& v = obs_[k].v_cam;
    for (int j = 0; j < n_pred; ++j) {
      const double d = v.dot(pred_[j].v_c);
      if (d > best_dot_[k]) best_dot_[k] = d, best_pred_[k] = j;
      if (!excluded_[k] && d > best_obs_dot[j]) best_obs_dot[j] = d, best_obs_[j] = k;
    }
    const double var_att = best_pred_[k] >= 0 ? pred_[best_pred_[k]].var_att : 0.0;
    const double off_axis = std::acos(std::clamp(v.z(), -1.0, 1.0));
    double r = opt_.gate_sigma * std::sqrt(obs_[k].sigma * obs_[k].sigma + var_att) +
               opt_.scale_tolerance * off_axis;
    r = std::max(r, min_gate_);
    gate_rad_[k] = r;
    gate_cos_[k] = std::cos(r);
  }
}

// An observation with two predicted stars inside its gate, or a predicted star with two
// observations inside theirs (a close pair, a false star next to a real one), cannot be
// told apart at this noise: such pairs are left out rather than guessed.
void VerifyRefinement::keepUnambiguous() {
  const int n_pred = static_cast<int>(pred_.size());
  std::vector<int> in_gate_obs(n_obs_, 0), in_gate_pred(n_pred, 0);
  for (int k = 0; k < n_obs_; ++k) {
    if (excluded_[k]) continue;
    const Vec3& v = obs_[k].v_cam;
    for (int j = 0; j < n_pred; ++j)
      if (v.dot(pred_[j].v_c) >= gate_cos_[k]) ++in_gate_obs[k], ++in_gate_pred[j];
  }
  matches_.clear();
  std::fill(ambiguous_.begin(), ambiguous_.end(), 0);
  for (int k = 0; k < n_obs_; ++k) {
    const int j = best_pred_[k];
    if (excluded_[k] || j < 0 || best_obs_[j] != k || best_dot_[k] < gate_cos_[k]) continue;
    if (in_gate_obs[k] > 1 || in_gate_pred[j] > 1) {
      ambiguous_[k] = 1;
      continue;
    }
    matches_.push_back(makeMatch(k, pred_[j].star));
  }
}

// Near misses that passed the residual test stay matched (a star just outside its gate
// would otherwise flip in and out between rounds).
void VerifyRefinement::keepForced() {
  bool added = false;
  for (int k = 0; k < n_obs_; ++k) {
    if (forced_[k] < 0 || excluded_[k]) continue;
    const uint32_t star = static_cast<uint32_t>(forced_[k]);
    const bool taken = std::any_of(matches_.begin(), matches_.end(), [&](const StarMatch& mm) {
      return mm.obs_index == static_cast<uint32_t>(k) || mm.star_index == star;
    });
    if (taken) continue;
    matches_.push_back(makeMatch(k, star));
    added = true;
  }
  if (added) sortByObservation(matches_);
}

// Residual test: 2 * loss ~ chi-square(2n - 3) (wahba.hpp, seed 004 eq. 6.18); while it
// fails, the worst star is excluded for good and the rest re-solved.
bool VerifyRefinement::passesResidualTest(int& dropped) {
  const auto judge = [&]() { return judgeResiduals(); };
  const auto drop_and_resolve = [&](std::size_t worst) {
    excluded_[matches_[worst].obs_index] = 1;
    matches_.erase(matches_.begin() + static_cast<long>(worst));
    ++res_.outliers_removed;
    ++dropped;
    const WahbaSolution next = solveMatches({});
    if (!next.ok) return false;
    sol_ = next;
    return ++guard_ < guard_limit_;  // each re-solve is one round of the guard
  };
  const std::size_t min_keep = static_cast<std::size_t>(std::max(3, opt_.min_matches));
  return dropWorstWhileFailing(matches_.size(), min_keep, judge, drop_and_resolve) ==
         DropWorstOutcome::kAccepted;
}

DropWorstVerdict VerifyRefinement::judgeResiduals() {
  const Mat3 R_ci = sol_.q_ib.toRotationMatrix().transpose();
  double chi2 = 0, worst_z2 = -1;
  std::size_t worst = 0;
  for (std::size_t i = 0; i < matches_.size(); ++i) {
    const StarMatch& m = matches_[i];
    const Vec3& b = obs_[m.obs_index].v_cam;
    const double z2 = (b - R_ci * stars_[m.star_index].u_i).squaredNorm() /
                      (obs_[m.obs_index].sigma * obs_[m.obs_index].sigma);
    chi2 += z2;
    if (z2 > worst_z2) worst_z2 = z2, worst = i;
  }
  res_.chi2 = chi2;
  const int n = static_cast<int>(matches_.size());
  return {!(residual_test_ && n >= 3 &&
            chiSquareUpperTail(chi2, 2 * n - 3) < opt_.residual_alpha),
          worst};
}

// Near misses: fit them together with the matches and keep them while they pass the
// residual test. A partial match (an attitude off in roll) then moves to the full one;
// a truly displaced star fails the residual test and is excluded.
bool VerifyRefinement::absorbNearMisses() {
  if (findNearMisses() == 0) return false;
  const WahbaSolution next = solveMatches(near_);
  if (!next.ok) return false;
  sol_ = next;
  for (const auto& [k, j] : near_) {
    forced_[k] = static_cast<int>(pred_[j].star);
    matches_.push_back(makeMatch(k, pred_[j].star));
  }
  sortByObservation(matches_);
  return true;
}

// Unmatched, non-excluded observations whose nearest predicted star is unmatched and within
// near_miss_factor gate radii go to near_; also sets n_unmatched_ and near_p_.
int VerifyRefinement::findNearMisses() {
  near_.clear();
  const int n_pred = static_cast<int>(pred_.size());
  std::vector<char> pred_used(n_pred, 0), obs_used(n_obs_, 0);
  for (const StarMatch& mm : matches_) obs_used[mm.obs_index] = 1;
  for (int k = 0; k < n_obs_; ++k)
    if (obs_used[k] && best_pred_[k] >= 0) pred_used[best_pred_[k]] = 1;
  const int n_pred_free = std::max(0, n_pred - static_cast<int>(matches_.size()));
  n_unmatched_ = 0;
  double sum = 0;
  for (int k = 0; k < n_obs_; ++k) {
    if (obs_used[k] || excluded_[k] || ambiguous_[k]) continue;
    ++n_unmatched_;
    const double r = opt_.near_miss_factor * gate_rad_[k];
    sum += std::min(1.0, n_pred_free * kPi * r * r / p_.omega_fov);
    const int j = best_pred_[k];
    if (j < 0 || pred_used[j] || forced_[k] >= 0 || best_dot_[k] < std::cos(r)) continue;
    if (uniqueNearMiss(k, j, std::cos(r))) near_.push_back({k, j});
  }
  near_p_ = n_unmatched_ > 0 ? sum / n_unmatched_ : 0.0;
  return static_cast<int>(near_.size());
}

// Only an unambiguous near miss counts (and is fitted): no other predicted star near the
// observation, no other observation near the predicted star.
bool VerifyRefinement::uniqueNearMiss(int k, int j, double cos_r) const {
  const int n_pred = static_cast<int>(pred_.size());
  for (int jj = 0; jj < n_pred; ++jj)
    if (jj != j && obs_[k].v_cam.dot(pred_[jj].v_c) >= cos_r) return false;
  for (int kk = 0; kk < n_obs_; ++kk)
    if (kk != k && !excluded_[kk] && obs_[kk].v_cam.dot(pred_[j].v_c) >= cos_r) return false;
  return true;
}

WahbaSolution VerifyRefinement::solveMatches(const std::vector<std::pair<int, int>>& extra) const {
  std::vector<VectorObservation> vo;
  vo.reserve(matches_.size() + extra.size());
  for (const StarMatch& mm : matches_)
    vo.push_back({obs_[mm.obs_index].v_cam, stars_[mm.star_index].u_i, obs_[mm.obs_index].sigma});
  for (const auto& [k, j] : extra)
    vo.push_back({obs_[k].v_cam, stars_[pred_[j].star].u_i, obs_[k].sigma});
  return p_.solver.solve(vo);
}

StarMatch VerifyRefinement::makeMatch(int k, uint32_t star) const {
  StarMatch m;
  m.obs_index = k;
  m.star_index = star;
  m.catalog_id = stars_[star].id;
  return m;
}

// Residuals against the final attitude.
void VerifyRefinement::measureResiduals() {
  const Mat3 R_ci = res_.q_ic.toRotationMatrix().transpose();
  double sum2 = 0, sum2_px = 0;
  for (StarMatch& m : matches_) {
    const Vec3 v_pred = R_ci * stars_[m.star_index].u_i;
    const Vec3& v = obs_[m.obs_index].v_cam;
    m.residual = std::atan2(v.cross(v_pred).norm(), v.dot(v_pred));
    const auto px = p_.camera.vectorToPixel(v_pred);
    m.residual_px = px ? (*px - obs_[m.obs_index].px).norm() : 0.0;
    sum2 += m.residual * m.residual;
    sum2_px += m.residual_px * m.residual_px;
  }
  if (!matches_.empty()) {
    res_.rms_residual = std::sqrt(sum2 / matches_.size());
    res_.rms_residual_px = std::sqrt(sum2_px / matches_.size());
  }
}

// False-match probability (model in verify.hpp) of the final match set.
double VerifyRefinement::falseMatchProbability(double attitudes_examined,
                                               int free_matches) const {
  const int n = std::max(0, n_obs_ - free_matches);
  const int m = std::max(0, static_cast<int>(matches_.size()) - free_matches);
  double sum_p = 0;
  for (int k = 0; k < n_obs_; ++k) {
    // A kept near miss was accepted within near_miss_factor gate radii.
    const double r = gate_rad_[k] * (forced_[k] >= 0 ? opt_.near_miss_factor : 1.0);
    sum_p += std::min(1.0, res_.predicted_in_fov * kPi * r * r / p_.omega_fov);
  }
  const double p_chance = n_obs_ > 0 ? sum_p / n_obs_ : 1.0;
  return std::min(1.0, std::max(1.0, attitudes_examined) * binomialUpperTail(n, m, p_chance));
}

// Accepts res_ or names the first test it fails.
void VerifyRefinement::decide(double near_tail) {
  if (!opt_.enabled) {
    res_.accepted = sol_.ok;
    if (!res_.accepted) res_.reason = "attitude solver failed";
    return;
  }
  if (static_cast<int>(matches_.size()) < opt_.min_matches) {
    res_.reason = "only " + std::to_string(matches_.size()) + " stars matched (need " +
                  std::to_string(opt_.min_matches) + ")";
    return;
  }
  char buf[200];
  if (residual_failed_) {
    std::snprintf(buf, sizeof buf,
                  "residuals inconsistent with the centroid covariances (chi2 %.3g for %zu "
                  "stars after removing %d outliers)",
                  res_.chi2, matches_.size(), res_.outliers_removed);
    res_.reason = buf;
    return;
  }
  // Excluding stars one by one can carve a consistent subset out of any bad match; honest
  // error situations have few stars outside tolerance (seed 003 Table 2: one or two), so
  // more outliers than max_outlier_fraction of the kept matches (at least two) is a failure.
  const int max_outliers = std::max(
      2, static_cast<int>(opt_.max_outlier_fraction * static_cast<double>(matches_.size())));
  if (res_.outliers_removed > max_outliers) {
    std::snprintf(buf, sizeof buf, "%d outliers removed from %zu matched stars (at most %d)",
                  res_.outliers_removed, matches_.size(), max_outliers);
    res_.reason = buf;
    return;
  }
  if (res_.false_match_probability > opt_.false_match_threshold) {
    std::snprintf(buf, sizeof buf, "false-match probability %.3g above the threshold %.3g",
                  res_.false_match_probability, opt_.false_match_threshold);
    res_.reason = buf;
    return;
  }
  if (near_tail < opt_.residual_alpha) {
    std::snprintf(buf, sizeof buf,
                  "partial match: %d unmatched stars lie just outside their gates (P %.3g)",
                  res_.near_misses, near_tail);
    res_.reason = buf;
    return;
  }
  res_.accepted = true;
}

}  // namespace st
