#include "sensors/identify/verify.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/conventions.hpp"
#include "sensors/attitude/drop_worst.hpp"
#include "sensors/identify/verify_refine.hpp"

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

// The rounds share their state, so they run in an object of their own (verify_refine.hpp).
VerificationResult Verifier::refine(const std::vector<StarObservation>& obs, Quat q_ic,
                                    Mat3 cov_cam, double attitudes_examined,
                                    int free_matches) const {
  const VerifierParts parts{db_, camera_, solver_, options_, omega_fov_, cone_radius_};
  VerifyRefinement refinement(parts, obs, q_ic, cov_cam);
  return refinement.run(attitudes_examined, free_matches);
}

}  // namespace st
