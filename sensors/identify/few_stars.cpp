#include "sensors/identify/few_stars.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

#include "common/check.hpp"
#include "common/chi_square.hpp"
#include "common/conventions.hpp"
#include "sensors/identify/algorithms.hpp"

namespace st::identify_detail {

namespace {

struct Candidate {
  std::array<uint32_t, 3> star{};
  WahbaSolution sol;
};

/// Fraction of database stars with V in [lo, hi] (`mags` sorted).
double fractionIn(const std::vector<float>& mags, double lo, double hi) {
  const auto a = std::lower_bound(mags.begin(), mags.end(), static_cast<float>(lo));
  const auto b = std::upper_bound(mags.begin(), mags.end(), static_cast<float>(hi));
  return mags.empty() ? 1.0 : double(b - a) / double(mags.size());
}

}  // namespace

double magnitudeChi2(const std::vector<StarObservation>& obs, const StarDatabase& db,
                     const int* obs_idx, const uint32_t* star_idx, int n, double sigma_m) {
  // Seed 000: only relative magnitudes are reliable, so the zero point is the mean offset.
  double r[3], zp = 0;
  for (int s = 0; s < n; ++s) {
    r[s] = db.stars()[star_idx[s]].mag + 2.5 * std::log10(obs[obs_idx[s]].brightness);
    zp += r[s] / n;
  }
  double chi2 = 0;
  for (int s = 0; s < n; ++s) chi2 += (r[s] - zp) * (r[s] - zp);
  return chi2 / (sigma_m * sigma_m);
}

FewStarOutcome identifyFewStars(SearchContext& ctx, const WahbaSolver& solver) {
  const int n = ctx.n;
  ST_ASSERT((n == 2 || n == 3) && static_cast<int>(ctx.obs.size()) == n);
  const double sigma_m = ctx.opt.magnitude_sigma;
  ST_ASSERT(sigma_m > 0);
  const VerifyOptions& vo = ctx.opt.verify;
  FewStarOutcome out;
  for (int s = 0; s < n; ++s)
    if (!(ctx.obs[s].brightness > 0)) {
      out.reason = "magnitude tie-break: observation " + std::to_string(s) + " has no brightness";
      return out;
    }
  const double chi2_max = chiSquareQuantile(1 - vo.residual_alpha, n - 1);
  const double window = sigma_m * std::sqrt(2 * chiSquareQuantile(1 - vo.residual_alpha, 1));
  const int obs_idx[3] = {0, 1, 2};

  std::vector<Candidate> kept;
  const auto consider = [&](const uint32_t* stars) {
    ++out.geometric;
    if (magnitudeChi2(ctx.obs, ctx.db, obs_idx, stars, n, sigma_m) > chi2_max) return false;
    ++out.magnitude_ok;
    Candidate c;
    std::copy(stars, stars + n, c.star.begin());
    std::vector<VectorObservation> v;
    for (int s = 0; s < n; ++s) v.push_back({ctx.v(s), ctx.u(stars[s]), ctx.obs[s].sigma});
    c.sol = solver.solve(v);
    if (c.sol.ok) kept.push_back(c);
    return false;  // every pattern: uniqueness needs all of them
  };
  if (n == 3) {
    forEachCatalogTriangle(ctx, 0, 1, 2, [&](uint32_t a, uint32_t b, uint32_t c) {
      const uint32_t st[3] = {a, b, c};
      return consider(st);
    });
  } else {
    const PairSlice s = ctx.slice(0, 1);
    ctx.addAttitudes(2.0 * s.size());
    for (const StarPair* p = s.begin; p != s.end; ++p)
      for (int o = 0; o < 2; ++o) {
        const uint32_t st[2] = {o ? p->b : p->a, o ? p->a : p->b};
        consider(st);
      }
  }
  out.any_candidate = out.geometric > 0;

  // Absent stars: a catalog star in the image brighter than a matched one would have been seen.
  const CameraModel& cam = ctx.camera;
  const double margin = std::max(2.0, vo.edge_margin_px);
  std::vector<uint32_t> cone;
  std::vector<Candidate> survivors;
  for (const Candidate& c : kept) {
    double faintest = -1e9;
    for (int s = 0; s < n; ++s)
      faintest = std::max<double>(faintest, ctx.db.stars()[c.star[s]].mag);
    const Mat3 R_ib = c.sol.q_ib.toRotationMatrix();
    ctx.db.coneQuery(R_ib.col(2), cam.halfDiagonalFov(), cone);
    bool absent = false;
    for (uint32_t k : cone) {
      if (std::find(c.star.begin(), c.star.begin() + n, k) != c.star.begin() + n) continue;
      if (ctx.db.stars()[k].mag >= faintest - window) continue;
      const auto px = cam.vectorToPixel(R_ib.transpose() * ctx.u(k));
      if (!px || px->x() < margin || px->y() < margin || px->x() > cam.width() - 1 - margin ||
          px->y() > cam.height() - 1 - margin)
        continue;
      bool near_obs = false;  // blended with an observation: not absent
      for (int s = 0; s < n; ++s) near_obs = near_obs || (*px - ctx.obs[s].px).norm() < 3.0;
      if (!near_obs) {
        absent = true;
        break;
      }
    }
    if (!absent) survivors.push_back(c);
  }
  out.survivors = static_cast<int>(survivors.size());
  std::ostringstream why;
  why << "magnitude tie-break over " << n << " stars: " << out.geometric
      << " catalog patterns fit the geometry, " << out.magnitude_ok << " the magnitudes, "
      << out.survivors << " without an absent brighter star";
  if (survivors.size() != 1) {
    out.reason = why.str() + (survivors.empty() ? "" : ": ambiguous, refused");
    return out;
  }

  // The survivor, as the verifier would report it (verify.hpp).
  const Candidate& c = survivors.front();
  VerificationResult& r = out.result;
  r.q_ic = c.sol.q_ib;
  r.cov_cam = c.sol.cov_body;
  r.chi2 = 2 * c.sol.loss;
  const Mat3 R_ci = c.sol.q_ib.toRotationMatrix().transpose();
  double ss = 0, ss_px = 0;
  for (int s = 0; s < n; ++s) {
    StarMatch m;
    m.obs_index = static_cast<uint32_t>(s);
    m.star_index = c.star[s];
    m.catalog_id = ctx.db.stars()[c.star[s]].id;
    const Vec3 pred = R_ci * ctx.u(c.star[s]);
    m.residual = std::atan2(pred.cross(ctx.v(s)).norm(), pred.dot(ctx.v(s)));
    const auto px = cam.vectorToPixel(pred);
    m.residual_px = px ? (*px - ctx.obs[s].px).norm() : 0.0;
    ss += m.residual * m.residual;
    ss_px += m.residual_px * m.residual_px;
    r.matches.push_back(m);
  }
  r.rms_residual = std::sqrt(ss / n);
  r.rms_residual_px = std::sqrt(ss_px / n);

  // P_false (header).
  const double omega = double(cam.width()) * cam.height() * cam.pixelScale() * cam.pixelScale();
  const double n_fov = double(ctx.db.stars().size()) * omega / (4 * kPi);
  double p = 1;
  if (n == 3) {
    const Vec3 a = ctx.v(0) - ctx.v(2), b = ctx.v(1) - ctx.v(2);
    const double sin_phi = std::max(0.05, a.cross(b).norm() / (a.norm() * b.norm()));
    p = std::min(1.0, n_fov * 4 * ctx.tol(0, 2) * ctx.tol(1, 2) / sin_phi / omega);
  }
  std::vector<float> mags;
  mags.reserve(ctx.db.stars().size());
  for (const Star& s : ctx.db.stars()) mags.push_back(s.mag);
  std::sort(mags.begin(), mags.end());
  double q = 1;
  const double m0 = -2.5 * std::log10(ctx.obs[0].brightness);
  const double v0 = ctx.db.stars()[c.star[0]].mag;
  for (int s = 1; s < n; ++s) {
    const double need = v0 + (-2.5 * std::log10(ctx.obs[s].brightness) - m0);
    q *= fractionIn(mags, need - window, need + window);
  }
  r.predicted_in_fov = static_cast<int>(std::lround(n_fov));
  r.false_match_probability = std::min(1.0, std::max(1.0, ctx.attitudesExamined()) * p * q);
  const bool residual_ok = !(vo.residual_test && solver.minimisesLoss()) ||
                           chiSquareUpperTail(r.chi2, 2 * n - 3) >= vo.residual_alpha;
  std::ostringstream pf;
  pf << "; P_false " << r.false_match_probability << " (" << ctx.attitudesExamined()
     << " attitudes x p " << p << " x q " << q << ")";
  if (!residual_ok) {
    r.reason = why.str() + "; residual chi-square " + std::to_string(r.chi2) + " too large";
  } else if (r.false_match_probability > vo.false_match_threshold) {
    r.reason = why.str() + pf.str() + " above the threshold";
  } else {
    r.accepted = true;
    out.solved = true;
  }
  out.reason = r.accepted ? "" : r.reason;
  return out;
}

}  // namespace st::identify_detail
