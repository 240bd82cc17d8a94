#include "sensors/identify/verify.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "common/conventions.hpp"
#include "sensors/attitude/drop_worst.hpp"

namespace st {

double binomialUpperTail(int n, int m, double p) {
  if (m <= 0) return 1.0;
  if (m > n || p <= 0) return 0.0;
  if (p >= 1) return 1.0;
  double sum = 0;
  const double lp = std::log(p), lq = std::log1p(-p);
  for (int x = m; x <= n; ++x) {
    const double log_term = std::lgamma(n + 1.0) - std::lgamma(x + 1.0) -
                            std::lgamma(n - x + 1.0) + x * lp + (n - x) * lq;
    sum += std::exp(log_term);
  }
  return std::min(1.0, sum);
}

bool VerifyOptions::isValid(std::string* why) const {
  std::ostringstream e;
  auto bad = [&](const char* key, double v, const char* want) {
    e << "VerifyOptions." << key << " = " << v << ": " << want;
  };
  if (!(gate_sigma > 0))
    bad("gate_sigma", gate_sigma, "must be > 0");
  else if (!(min_gate_px >= 0))
    bad("min_gate_px", min_gate_px, "must be >= 0");
  else if (!(scale_tolerance >= 0 && scale_tolerance < 1))
    bad("scale_tolerance", scale_tolerance, "must be in [0, 1)");
  else if (!(false_match_threshold > 0 && false_match_threshold <= 1))
    bad("false_match_threshold", false_match_threshold, "must be in (0, 1]");
  else if (min_matches < 3)
    bad("min_matches", min_matches, "must be >= 3 (two stars fit any attitude)");
  else if (refine_iterations < 1)
    bad("refine_iterations", refine_iterations, "must be >= 1");
  else if (!(edge_margin_px >= 0))
    bad("edge_margin_px", edge_margin_px, "must be >= 0");
  else if (!(residual_alpha > 0 && residual_alpha < 1))
    bad("residual_alpha", residual_alpha, "must be in (0, 1)");
  else if (!(near_miss_factor >= 1))
    bad("near_miss_factor", near_miss_factor, "must be >= 1");
  else if (!(max_outlier_fraction >= 0 && max_outlier_fraction <= 1))
    bad("max_outlier_fraction", max_outlier_fraction, "must be in [0, 1]");
  const std::string msg = e.str();
  if (why) *why = msg;
  return msg.empty();
}

Verifier::Verifier(const StarDatabase& db, const CameraModel& camera, const WahbaSolver& solver,
                   VerifyOptions options)
    : db_(db), camera_(camera), solver_(solver), options_(options) {
  // Solid angle of the image, small-field approximation (pixel count x pixel solid angle).
  omega_fov_ = double(camera.width()) * camera.height() * camera.pixelScale() *
               camera.pixelScale();
  cone_radius_ = camera.halfDiagonalFov();
}

VerificationResult Verifier::verifySeeds(const std::vector<StarObservation>& obs,
                                         const std::vector<StarMatch>& seeds,
                                         double attitudes_examined) const {
  VerificationResult res;
  std::vector<VectorObservation> vo;
  vo.reserve(seeds.size());
  const auto& stars = db_.stars();
  for (const StarMatch& s : seeds)
    vo.push_back({obs[s.obs_index].v_cam, stars[s.star_index].u_i, obs[s.obs_index].sigma});
  WahbaSolution sol = solver_.solve(vo);
  // A seed set may hold a wrong pairing (a spike that fitted by chance): drop the seed with
  // the largest normalised residual while it is outside the gate, then re-solve.
  const auto judge = [&]() -> DropWorstVerdict {
    if (vo.size() <= 3) return {true, 0};
    const Mat3 R_ci = sol.q_ib.toRotationMatrix().transpose();
    std::size_t worst = 0;
    double worst_z = 0;
    for (std::size_t k = 0; k < vo.size(); ++k) {
      const double z = (vo[k].b - R_ci * vo[k].r).norm() / vo[k].sigma;
      if (z > worst_z) worst_z = z, worst = k;
    }
    return {worst_z <= options_.gate_sigma, worst};
  };
  const auto drop_and_resolve = [&](std::size_t worst) {
    vo.erase(vo.begin() + static_cast<long>(worst));
    sol = solver_.solve(vo);
    return sol.ok;
  };
  if (!sol.ok || dropWorstWhileFailing(vo.size(), 0, judge, drop_and_resolve) ==
                     DropWorstOutcome::kSolverFailed) {
    res.reason = "attitude from the seed stars failed: " + sol.reason;
    return res;
  }
  // Two stars fix an attitude: they match under any hypothesis and are no evidence.
  return refine(obs, sol.q_ib, sol.cov_body, attitudes_examined,
                std::min<int>(2, static_cast<int>(seeds.size())));
}

namespace {
struct Predicted {
  uint32_t star;
  Vec3 v_c;  // predicted direction, camera frame
  double var_att;  // [rad^2] per-axis variance of the direction from the attitude covariance
};
}  // namespace

VerificationResult Verifier::refine(const std::vector<StarObservation>& obs, Quat q_ic,
                                    Mat3 cov_cam, double attitudes_examined,
                                    int free_matches) const {
  VerificationResult res;
  const auto& stars = db_.stars();
  const int n_obs = static_cast<int>(obs.size());
  std::vector<uint32_t> cone;
  std::vector<Predicted> pred;
  std::vector<StarMatch> matches, prev;
  std::vector<int> best_pred(n_obs), best_obs;
  std::vector<double> gate_cos(n_obs), gate_rad(n_obs), best_dot(n_obs);
  std::vector<char> excluded(n_obs, 0), ambiguous(n_obs, 0);
  std::vector<int> forced(n_obs, -1);  // near misses kept as matches: star per observation
  const double min_gate = options_.min_gate_px * camera_.pixelScale();
  WahbaSolution sol;
  sol.ok = true;
  sol.q_ib = q_ic;  // WahbaSolution is frame-agnostic: here the camera's attitude
  sol.cov_body = cov_cam;
  bool residual_failed = false;

  // Mutual nearest neighbours inside the gates at the attitude `sol` (excluded observations
  // take no part); fills pred, best_pred, best_obs, gate_rad/cos and matches.
  auto match = [&]() {
    const Mat3 R_ic = sol.q_ib.toRotationMatrix();
    const Mat3 R_ci = R_ic.transpose();
    const Mat3 p = sol.cov_body;
    cone.clear();
    db_.coneQuery(R_ic.col(2), cone_radius_, cone);
    pred.clear();
    for (uint32_t s : cone) {
      const Vec3 v_c = R_ci * stars[s].u_i;
      if (v_c.z() <= 0 || !camera_.isVectorInImage(v_c, options_.edge_margin_px)) continue;
      // Direction error from a camera-frame rotation error dtheta is dtheta x v_c (eq. of
      // the linearised rotation); its per-axis variance is (tr P - v^T P v) / 2.
      const double var_att = std::max(0.0, (p.trace() - v_c.dot(p * v_c)) / 2.0);
      pred.push_back({s, v_c, var_att});
    }
    // Nearest predicted star of every observation, and its gate.
    const int n_pred = static_cast<int>(pred.size());
    best_obs.assign(n_pred, -1);
    std::vector<double> best_obs_dot(n_pred, -2.0);
    for (int k = 0; k < n_obs; ++k) {
      best_pred[k] = -1;
      best_dot[k] = -2.0;
      const Vec3& v = obs[k].v_cam;
      for (int j = 0; j < n_pred; ++j) {
        const double d = v.dot(pred[j].v_c);
        if (d > best_dot[k]) best_dot[k] = d, best_pred[k] = j;
        if (!excluded[k] && d > best_obs_dot[j]) best_obs_dot[j] = d, best_obs[j] = k;
      }
      const double var_att = best_pred[k] >= 0 ? pred[best_pred[k]].var_att : 0.0;
      const double off_axis = std::acos(std::clamp(v.z(), -1.0, 1.0));
      double r = options_.gate_sigma * std::sqrt(obs[k].sigma * obs[k].sigma + var_att) +
                 options_.scale_tolerance * off_axis;
      r = std::max(r, min_gate);
      gate_rad[k] = r;
      gate_cos[k] = std::cos(r);
    }
    // An observation with two predicted stars inside its gate, or a predicted star with two
    // observations inside theirs (a close pair, a false star next to a real one), cannot be
    // told apart at this noise: such pairs are left out rather than guessed.
    std::vector<int> in_gate_obs(n_obs, 0), in_gate_pred(n_pred, 0);
    for (int k = 0; k < n_obs; ++k) {
      if (excluded[k]) continue;
      const Vec3& v = obs[k].v_cam;
      for (int j = 0; j < n_pred; ++j)
        if (v.dot(pred[j].v_c) >= gate_cos[k]) ++in_gate_obs[k], ++in_gate_pred[j];
    }
    matches.clear();
    std::fill(ambiguous.begin(), ambiguous.end(), 0);
    for (int k = 0; k < n_obs; ++k) {
      const int j = best_pred[k];
      if (excluded[k] || j < 0 || best_obs[j] != k || best_dot[k] < gate_cos[k]) continue;
      if (in_gate_obs[k] > 1 || in_gate_pred[j] > 1) {
        ambiguous[k] = 1;
        continue;
      }
      StarMatch m;
      m.obs_index = k;
      m.star_index = pred[j].star;
      m.catalog_id = stars[pred[j].star].id;
      matches.push_back(m);
    }
    // Near misses that passed the residual test stay matched (a star just outside its gate
    // would otherwise flip in and out between rounds).
    bool added = false;
    for (int k = 0; k < n_obs; ++k) {
      if (forced[k] < 0 || excluded[k]) continue;
      const uint32_t star = static_cast<uint32_t>(forced[k]);
      const bool taken = std::any_of(matches.begin(), matches.end(), [&](const StarMatch& mm) {
        return mm.obs_index == static_cast<uint32_t>(k) || mm.star_index == star;
      });
      if (taken) continue;
      StarMatch m;
      m.obs_index = k;
      m.star_index = star;
      m.catalog_id = stars[star].id;
      matches.push_back(m);
      added = true;
    }
    if (added)
      std::sort(matches.begin(), matches.end(),
                [](const StarMatch& a, const StarMatch& b) { return a.obs_index < b.obs_index; });
    res.predicted_in_fov = n_pred;
  };

  // With scale slack (FOV search candidates) the residuals hold a scale error the centroid
  // covariances do not describe; such candidates are re-verified after the focal-length fit.
  const bool residual_test = options_.enabled && options_.residual_test &&
                             options_.scale_tolerance <= 0;
  const bool near_test = options_.enabled && options_.near_miss_test &&
                         options_.scale_tolerance <= 0;
  // Unmatched, non-excluded observations whose nearest predicted star is unmatched and within
  // near_miss_factor gate radii: (observation, prediction) pairs; also sets near_p, the mean
  // chance probability of such a near miss (model in verify.hpp).
  std::vector<std::pair<int, int>> near;
  int n_unmatched = 0;
  double near_p = 0;
  auto findNearMisses = [&]() {
    near.clear();
    const int n_pred = static_cast<int>(pred.size());
    std::vector<char> pred_used(n_pred, 0), obs_used(n_obs, 0);
    for (const StarMatch& mm : matches) obs_used[mm.obs_index] = 1;
    for (int k = 0; k < n_obs; ++k)
      if (obs_used[k] && best_pred[k] >= 0) pred_used[best_pred[k]] = 1;
    const int n_pred_free = std::max(0, n_pred - static_cast<int>(matches.size()));
    n_unmatched = 0;
    double sum = 0;
    for (int k = 0; k < n_obs; ++k) {
      if (obs_used[k] || excluded[k] || ambiguous[k]) continue;
      ++n_unmatched;
      const double r = options_.near_miss_factor * gate_rad[k];
      sum += std::min(1.0, n_pred_free * kPi * r * r / omega_fov_);
      const int j = best_pred[k];
      if (j < 0 || pred_used[j] || forced[k] >= 0 || best_dot[k] < std::cos(r)) continue;
      // Only an unambiguous near miss counts (and is fitted): no other predicted star near
      // the observation, no other observation near the predicted star.
      bool unique = true;
      for (int jj = 0; jj < n_pred && unique; ++jj)
        if (jj != j && obs[k].v_cam.dot(pred[jj].v_c) >= std::cos(r)) unique = false;
      for (int kk = 0; kk < n_obs && unique; ++kk)
        if (kk != k && !excluded[kk] && obs[kk].v_cam.dot(pred[j].v_c) >= std::cos(r))
          unique = false;
      if (unique) near.push_back({k, j});
    }
    near_p = n_unmatched > 0 ? sum / n_unmatched : 0.0;
    return static_cast<int>(near.size());
  };
  auto solveMatches = [&](const std::vector<std::pair<int, int>>& extra) {
    std::vector<VectorObservation> vo;
    vo.reserve(matches.size() + extra.size());
    for (const StarMatch& mm : matches)
      vo.push_back({obs[mm.obs_index].v_cam, stars[mm.star_index].u_i, obs[mm.obs_index].sigma});
    for (const auto& [k, j] : extra)
      vo.push_back({obs[k].v_cam, stars[pred[j].star].u_i, obs[k].sigma});
    return solver_.solve(vo);
  };
  bool rematch = true, settled = false;
  const int guard_limit = 3 * n_obs + 10;
  for (int guard = 0; guard < guard_limit && !settled; ++guard) {
    const bool fresh = rematch;
    rematch = false;
    if (fresh) {
      prev.clear();
      for (int iter = 0; iter < std::max(1, options_.refine_iterations); ++iter) {
        match();
        if (matches.size() < 2) break;
        const WahbaSolution next = solveMatches({});
        if (!next.ok) break;
        sol = next;
        const bool same = prev.size() == matches.size() &&
                          std::equal(prev.begin(), prev.end(), matches.begin(),
                                     [](const StarMatch& a, const StarMatch& b) {
                                       return a.obs_index == b.obs_index &&
                                              a.star_index == b.star_index;
                                     });
        if (same) break;
        prev = matches;
      }
    }
    // Residual test: 2 * loss ~ chi-square(2n - 3) (wahba.hpp, seed 004 eq. 6.18); while it
    // fails, the worst star is excluded for good and the rest re-solved.
    const int nm = static_cast<int>(matches.size());
    if (nm < 2) break;
    const auto judge = [&]() -> DropWorstVerdict {
      const Mat3 R_ci = sol.q_ib.toRotationMatrix().transpose();
      double chi2 = 0, worst_z2 = -1;
      std::size_t worst = 0;
      for (std::size_t i = 0; i < matches.size(); ++i) {
        const StarMatch& m = matches[i];
        const Vec3& b = obs[m.obs_index].v_cam;
        const double z2 = (b - R_ci * stars[m.star_index].u_i).squaredNorm() /
                          (obs[m.obs_index].sigma * obs[m.obs_index].sigma);
        chi2 += z2;
        if (z2 > worst_z2) worst_z2 = z2, worst = i;
      }
      res.chi2 = chi2;
      const int n = static_cast<int>(matches.size());
      return {!(residual_test && n >= 3 &&
                chiSquareUpperTail(chi2, 2 * n - 3) < options_.residual_alpha),
              worst};
    };
    int dropped = 0;
    const auto drop_and_resolve = [&](std::size_t worst) {
      excluded[matches[worst].obs_index] = 1;
      matches.erase(matches.begin() + static_cast<long>(worst));
      ++res.outliers_removed;
      ++dropped;
      const WahbaSolution next = solveMatches({});
      if (!next.ok) return false;
      sol = next;
      return ++guard < guard_limit;  // each re-solve is one round of the guard
    };
    const std::size_t min_keep = static_cast<std::size_t>(std::max(3, options_.min_matches));
    if (dropWorstWhileFailing(matches.size(), min_keep, judge, drop_and_resolve) !=
        DropWorstOutcome::kAccepted) {
      residual_failed = true;
      break;
    }
    // The set was edited (outliers out, near misses in): match again at the new attitude.
    if (dropped > 0 || !fresh) {
      rematch = true;
      continue;
    }
    // Near misses: fit them together with the matches and keep them while they pass the
    // residual test. A partial match (an attitude off in roll) then moves to the full one;
    // a truly displaced star fails the residual test above and is excluded.
    if (near_test && findNearMisses() > 0) {
      const WahbaSolution next = solveMatches(near);
      if (next.ok) {
        sol = next;
        for (const auto& [k, j] : near) {
          forced[k] = static_cast<int>(pred[j].star);
          StarMatch mm;
          mm.obs_index = k;
          mm.star_index = pred[j].star;
          mm.catalog_id = stars[pred[j].star].id;
          matches.push_back(mm);
        }
        std::sort(matches.begin(), matches.end(),
                  [](const StarMatch& a, const StarMatch& b) { return a.obs_index < b.obs_index; });
        continue;
      }
    }
    settled = true;
  }
  if (!settled && !residual_failed && matches.size() >= 2 && residual_test)
    residual_failed = true;  // never settled: do not trust it

  res.q_ic = canonical(sol.q_ib);
  res.cov_cam = sol.cov_body;
  // Residuals against the final attitude.
  const Mat3 R_ci = res.q_ic.toRotationMatrix().transpose();
  double sum2 = 0, sum2_px = 0;
  for (StarMatch& m : matches) {
    const Vec3 v_pred = R_ci * stars[m.star_index].u_i;
    const Vec3& v = obs[m.obs_index].v_cam;
    m.residual = std::atan2(v.cross(v_pred).norm(), v.dot(v_pred));
    const auto px = camera_.vectorToPixel(v_pred);
    m.residual_px = px ? (*px - obs[m.obs_index].px).norm() : 0.0;
    sum2 += m.residual * m.residual;
    sum2_px += m.residual_px * m.residual_px;
  }
  if (!matches.empty()) {
    res.rms_residual = std::sqrt(sum2 / matches.size());
    res.rms_residual_px = std::sqrt(sum2_px / matches.size());
  }
  res.matches = matches;

  // False-match probability (model in verify.hpp) of the final match set.
  const int n = std::max(0, n_obs - free_matches);
  const int m = std::max(0, static_cast<int>(matches.size()) - free_matches);
  double sum_p = 0;
  for (int k = 0; k < n_obs; ++k) {
    // A kept near miss was accepted within near_miss_factor gate radii.
    const double r = gate_rad[k] * (forced[k] >= 0 ? options_.near_miss_factor : 1.0);
    sum_p += std::min(1.0, res.predicted_in_fov * kPi * r * r / omega_fov_);
  }
  const double p_chance = n_obs > 0 ? sum_p / n_obs : 1.0;
  res.false_match_probability =
      std::min(1.0, std::max(1.0, attitudes_examined) * binomialUpperTail(n, m, p_chance));

  // Near misses left after the refits (model in verify.hpp).
  double near_tail = 1.0;
  if (near_test && !matches.empty()) {
    res.near_misses = findNearMisses();
    near_tail = binomialUpperTail(n_unmatched, res.near_misses, near_p);
  }

  if (!options_.enabled) {
    res.accepted = sol.ok;
    if (!res.accepted) res.reason = "attitude solver failed";
    return res;
  }
  if (static_cast<int>(matches.size()) < options_.min_matches) {
    res.reason = "only " + std::to_string(matches.size()) + " stars matched (need " +
                 std::to_string(options_.min_matches) + ")";
    return res;
  }
  char buf[200];
  if (residual_failed) {
    std::snprintf(buf, sizeof buf,
                  "residuals inconsistent with the centroid covariances (chi2 %.3g for %zu "
                  "stars after removing %d outliers)",
                  res.chi2, matches.size(), res.outliers_removed);
    res.reason = buf;
    return res;
  }
  // Excluding stars one by one can carve a consistent subset out of any bad match; honest
  // error situations have few stars outside tolerance (seed 003 Table 2: one or two), so
  // more outliers than max_outlier_fraction of the kept matches (at least two) is a failure.
  const int max_outliers = std::max(
      2, static_cast<int>(options_.max_outlier_fraction * static_cast<double>(matches.size())));
  if (res.outliers_removed > max_outliers) {
    std::snprintf(buf, sizeof buf, "%d outliers removed from %zu matched stars (at most %d)",
                  res.outliers_removed, matches.size(), max_outliers);
    res.reason = buf;
    return res;
  }
  if (res.false_match_probability > options_.false_match_threshold) {
    std::snprintf(buf, sizeof buf, "false-match probability %.3g above the threshold %.3g",
                  res.false_match_probability, options_.false_match_threshold);
    res.reason = buf;
    return res;
  }
  if (near_tail < options_.residual_alpha) {
    std::snprintf(buf, sizeof buf,
                  "partial match: %d unmatched stars lie just outside their gates (P %.3g)",
                  res.near_misses, near_tail);
    res.reason = buf;
    return res;
  }
  res.accepted = true;
  return res;
}

}  // namespace st
