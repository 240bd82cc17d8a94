#include "sensors/identify/verify.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "common/conventions.hpp"

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
  WahbaSolution sol;
  // A seed set may hold a wrong pairing (a spike that fitted by chance): drop the seed with
  // the largest normalised residual while it is outside the gate, then re-solve.
  for (;;) {
    sol = solver_.solve(vo);
    if (!sol.ok) {
      res.reason = "attitude from the seed stars failed: " + sol.reason;
      return res;
    }
    if (vo.size() <= 3) break;
    const Mat3 r_bi = sol.q_ib.toRotationMatrix().transpose();
    std::size_t worst = 0;
    double worst_z = 0;
    for (std::size_t k = 0; k < vo.size(); ++k) {
      const double z = (vo[k].b - r_bi * vo[k].r).norm() / vo[k].sigma;
      if (z > worst_z) worst_z = z, worst = k;
    }
    if (worst_z <= options_.gate_sigma) break;
    vo.erase(vo.begin() + worst);
  }
  // Two stars fix an attitude: they match under any hypothesis and are no evidence.
  return refine(obs, sol.q_ib, sol.cov_body, attitudes_examined,
                std::min<int>(2, static_cast<int>(seeds.size())));
}

VerificationResult Verifier::verifyAttitude(const std::vector<StarObservation>& obs,
                                            const Quat& q_ib, const Mat3& cov_body,
                                            double attitudes_examined, int free_matches) const {
  return refine(obs, q_ib, cov_body, attitudes_examined, free_matches);
}

namespace {
struct Predicted {
  uint32_t star;
  Vec3 v_b;
  double var_att;  // [rad^2] per-axis variance of the direction from the attitude covariance
};
}  // namespace

VerificationResult Verifier::refine(const std::vector<StarObservation>& obs, Quat q_ib,
                                    Mat3 cov_body, double attitudes_examined,
                                    int free_matches) const {
  VerificationResult res;
  const auto& stars = db_.stars();
  const int n_obs = static_cast<int>(obs.size());
  std::vector<uint32_t> cone;
  std::vector<Predicted> pred;
  std::vector<StarMatch> matches, prev;
  std::vector<int> best_pred(n_obs);
  std::vector<double> gate_cos(n_obs), gate_rad(n_obs), best_dot(n_obs);
  const double min_gate = options_.min_gate_px * camera_.pixelScale();
  WahbaSolution sol;
  sol.ok = true;
  sol.q_ib = q_ib;
  sol.cov_body = cov_body;

  for (int iter = 0; iter < std::max(1, options_.refine_iterations); ++iter) {
    const Mat3 r_ib = sol.q_ib.toRotationMatrix();
    const Mat3 r_bi = r_ib.transpose();
    const Mat3 p = sol.cov_body;
    cone.clear();
    db_.coneQuery(r_ib.col(2), cone_radius_, cone);
    pred.clear();
    for (uint32_t s : cone) {
      const Vec3 v_b = r_bi * stars[s].u_i;
      if (v_b.z() <= 0 || !camera_.isVectorInImage(v_b, options_.edge_margin_px)) continue;
      // Direction error from a body-frame rotation error dtheta is dtheta x v_b (eq. of
      // the linearised rotation); its per-axis variance is (tr P - v^T P v) / 2.
      const double var_att = std::max(0.0, (p.trace() - v_b.dot(p * v_b)) / 2.0);
      pred.push_back({s, v_b, var_att});
    }
    // Nearest predicted star of every observation, and its gate.
    const int n_pred = static_cast<int>(pred.size());
    std::vector<int> best_obs(n_pred, -1);
    std::vector<double> best_obs_dot(n_pred, -2.0);
    for (int k = 0; k < n_obs; ++k) {
      best_pred[k] = -1;
      best_dot[k] = -2.0;
      const Vec3& v = obs[k].v_cam;
      for (int j = 0; j < n_pred; ++j) {
        const double d = v.dot(pred[j].v_b);
        if (d > best_dot[k]) best_dot[k] = d, best_pred[k] = j;
        if (d > best_obs_dot[j]) best_obs_dot[j] = d, best_obs[j] = k;
      }
      const double var_att = best_pred[k] >= 0 ? pred[best_pred[k]].var_att : 0.0;
      const double off_axis = std::acos(std::clamp(v.z(), -1.0, 1.0));
      double r = options_.gate_sigma * std::sqrt(obs[k].sigma * obs[k].sigma + var_att) +
                 options_.scale_tolerance * off_axis;
      r = std::max(r, min_gate);
      gate_rad[k] = r;
      gate_cos[k] = std::cos(r);
    }
    matches.clear();
    for (int k = 0; k < n_obs; ++k) {
      const int j = best_pred[k];
      if (j < 0 || best_obs[j] != k || best_dot[k] < gate_cos[k]) continue;
      StarMatch m;
      m.obs_index = k;
      m.star_index = pred[j].star;
      m.catalog_id = stars[pred[j].star].id;
      matches.push_back(m);
    }
    res.predicted_in_fov = n_pred;
    if (matches.size() < 2) break;
    std::vector<VectorObservation> vo;
    vo.reserve(matches.size());
    for (const StarMatch& m : matches)
      vo.push_back({obs[m.obs_index].v_cam, stars[m.star_index].u_i, obs[m.obs_index].sigma});
    const WahbaSolution next = solver_.solve(vo);
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

  res.q_ib = canonical(sol.q_ib);
  res.cov_body = sol.cov_body;
  // Residuals against the final attitude.
  const Mat3 r_bi = res.q_ib.toRotationMatrix().transpose();
  double sum2 = 0, sum2_px = 0;
  for (StarMatch& m : matches) {
    const Vec3 v_pred = r_bi * stars[m.star_index].u_i;
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

  // False-match probability (model in verify.hpp).
  const int n = std::max(0, n_obs - free_matches);
  const int m = std::max(0, static_cast<int>(matches.size()) - free_matches);
  double sum_p = 0;
  for (int k = 0; k < n_obs; ++k)
    sum_p += std::min(1.0, res.predicted_in_fov * kPi * gate_rad[k] * gate_rad[k] / omega_fov_);
  const double p_chance = n_obs > 0 ? sum_p / n_obs : 1.0;
  res.false_match_probability =
      std::min(1.0, std::max(1.0, attitudes_examined) * binomialUpperTail(n, m, p_chance));

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
  if (res.false_match_probability > options_.false_match_threshold) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "false-match probability %.3g above the threshold %.3g",
                  res.false_match_probability, options_.false_match_threshold);
    res.reason = buf;
    return res;
  }
  res.accepted = true;
  return res;
}

}  // namespace st
