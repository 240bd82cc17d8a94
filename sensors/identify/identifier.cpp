#include "sensors/identify/identifier.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/check.hpp"
#include "common/conventions.hpp"
#include "sensors/identify/few_stars.hpp"
#include "sensors/identify/search_context.hpp"

namespace st {

const char* toString(IdentifyStatus s) {
  switch (s) {
    case IdentifyStatus::Solved: return "solved";
    case IdentifyStatus::TooFewStars: return "too_few_stars";
    case IdentifyStatus::NoMatch: return "no_match";
    case IdentifyStatus::Rejected: return "rejected";
  }
  return "unknown";
}

// ---- PartnerLists / StarCounter ----------------------------------------------------------

void PartnerLists::reset(std::size_t n_stars) {
  if (stamp_.size() != n_stars) {
    stamp_.assign(n_stars, 0);
    head_.assign(n_stars, kNone);
    epoch_ = 0;
  }
}

void PartnerLists::push(uint32_t a, uint32_t b) {
  const uint32_t e = static_cast<uint32_t>(partner_.size());
  partner_.push_back(b);
  next_.push_back(has(a) ? head_[a] : kNone);
  head_[a] = e;
  stamp_[a] = epoch_;
}

void PartnerLists::build(const PairSlice& s) {
  ++epoch_;
  partner_.clear();
  next_.clear();
  for (const StarPair* p = s.begin; p != s.end; ++p) {
    push(p->a, p->b);
    push(p->b, p->a);
  }
}

void StarCounter::reset(std::size_t n_stars) {
  if (stamp_.size() != n_stars) {
    stamp_.assign(n_stars, 0);
    count_.assign(n_stars, 0);
    tag_.assign(n_stars, 0);
    epoch_ = 1;
  }
}

// ---- SearchContext -------------------------------------------------------------------------

SearchContext::SearchContext(const std::vector<StarObservation>& obs_, const StarDatabase& db_,
                             const CameraModel& camera_, const IdentifyOptions& opt_,
                             const Verifier& verifier, int n_used,
                             std::vector<PartnerLists>& lists,
                             std::vector<StarCounter>& counters)
    : obs(obs_), db(db_), camera(camera_), opt(opt_), n(n_used), verifier_(verifier),
      lists_(lists), counters_(counters) {
  theta_.assign(n * n, 0);
  tol_.assign(n * n, 0);
  cos_lo_.assign(n * n, 2.0);
  cos_hi_.assign(n * n, 2.0);
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const Vec3 &a = obs[i].v_cam, &b = obs[j].v_cam;
      const double th = std::atan2(a.cross(b).norm(), a.dot(b));
      // Seed 000 eq. (14): search [theta - eps, theta + eps]; eps from the two centroid
      // sigmas (the angle error has variance sigma_i^2 + sigma_j^2) plus the scale slack.
      const double eps = opt.pair_sigma * std::hypot(obs[i].sigma, obs[j].sigma) +
                         opt.scale_tolerance * th;
      theta_[i * n + j] = theta_[j * n + i] = th;
      tol_[i * n + j] = tol_[j * n + i] = eps;
      cos_lo_[i * n + j] = cos_lo_[j * n + i] = std::cos(std::min(kPi, th + eps));
      cos_hi_[i * n + j] = cos_hi_[j * n + i] = std::cos(std::max(0.0, th - eps));
    }
}

PairSlice SearchContext::slice(int i, int j) {
  const double th = theta(i, j), eps = tol(i, j);
  PairSlice s = db.pairsInRange(std::max(0.0, th - eps), th + eps);
  candidates_ += static_cast<long>(s.size());
  return s;
}

bool SearchContext::sameHandedness(int i, int j, int k, uint32_t a, uint32_t b,
                                   uint32_t c) const {
  const double so = v(i).dot(v(j).cross(v(k)));
  const double sc = u(a).dot(u(b).cross(u(c)));
  return (so > 0) == (sc > 0);
}

bool SearchContext::tryHypothesis(const std::vector<StarMatch>& seeds) {
  any_hypothesis = true;
  ++hypotheses;
  const auto t0 = std::chrono::steady_clock::now();
  VerificationResult r = verifier_.verifySeeds(obs, seeds, std::max(1.0, attitudes_));
  verify_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (r.accepted) {
    accepted = std::move(r);
    solved = true;
    return true;
  }
  if (hypotheses == 1 || r.matches.size() > best_rejected.matches.size()) best_rejected = r;
  return false;
}

bool SearchContext::done() const {
  if (solved || hypotheses >= opt.max_verifications || candidates_ >= opt.max_candidates)
    return true;
  return opt.deadline && (++done_calls_ & 255u) == 0 &&
         std::chrono::steady_clock::now() >= *opt.deadline;
}

// ---- StarIdentifier --------------------------------------------------------------------------

bool IdentifyOptions::isValid(std::string* why) const {
  std::ostringstream e;
  auto bad = [&](const char* key, double v, const char* want) {
    e << "IdentifyOptions." << key << " = " << v << ": " << want;
  };
  std::string inner;
  if (!(pair_sigma > 0))
    bad("pair_sigma", pair_sigma, "must be > 0");
  else if (!(scale_tolerance >= 0 && scale_tolerance < 1))
    bad("scale_tolerance", scale_tolerance, "must be in [0, 1)");
  else if (max_stars < 3)
    bad("max_stars", max_stars, "must be >= 3");
  else if (max_stars_retry < 0)
    bad("max_stars_retry", max_stars_retry, "must be >= 0 (<= max_stars: no retry)");
  else if (max_verifications < 1)
    bad("max_verifications", max_verifications, "must be >= 1");
  else if (max_candidates < 1)
    bad("max_candidates", static_cast<double>(max_candidates), "must be >= 1");
  else if (!(magnitude_sigma >= 0 && std::isfinite(magnitude_sigma)))
    bad("magnitude_sigma", magnitude_sigma, "must be >= 0 (0 = no magnitude tie-break)");
  else if (!WahbaSolver::create(solver, &inner))
    e << "IdentifyOptions.solver: " << inner;
  else if (!verify.isValid(&inner))
    e << "IdentifyOptions.verify: " << inner;
  const std::string msg = e.str();
  if (why) *why = msg;
  return msg.empty();
}

struct StarIdentifier::Scratch {
  std::vector<PartnerLists> lists = std::vector<PartnerLists>(4);
  std::vector<StarCounter> counters = std::vector<StarCounter>(4);
};

StarIdentifier::StarIdentifier(const IdentifyOptions& options)
    : options_(options), solver_(WahbaSolver::create(options.solver)),
      scratch_(std::make_unique<Scratch>()) {
  ST_ASSERT(solver_ != nullptr);  // options validated by create()
}
StarIdentifier::~StarIdentifier() = default;

IdentifyResult StarIdentifier::identify(const std::vector<StarObservation>& obs,
                                        const StarDatabase& db,
                                        const CameraModel& camera) const {
  const auto t0 = std::chrono::steady_clock::now();
  IdentifyResult res;
  res.algorithm = name();
  auto finishWith = [&](SearchContext& c) { return finishResult(c, res, t0); };
  auto finish = [&] {
    res.timing.total_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    res.timing.pattern_ms = std::max(0.0, res.timing.total_ms - res.timing.verify_ms);
    return res;
  };
  ST_ASSERT(options_.solver == solver_->name());  // fixed at construction
  Scratch& sc = *scratch_;
  const int n = std::min<int>(static_cast<int>(obs.size()), std::max(3, options_.max_stars));
  res.stars_used = n;
  const int n_obs = static_cast<int>(obs.size());
  if (options_.magnitude_sigma > 0 && n_obs >= 2 && n_obs <= 3 && n_obs < starsNeeded()) {
    for (auto& l : sc.lists) l.reset(db.stars().size());
    VerifyOptions vopt = options_.verify;
    vopt.scale_tolerance = std::max(vopt.scale_tolerance, options_.scale_tolerance);
    const Verifier verifier(db, camera, *solver_, vopt);
    SearchContext ctx(obs, db, camera, options_, verifier, n_obs, sc.lists, sc.counters);
    const auto ts = std::chrono::steady_clock::now();
    const identify_detail::FewStarOutcome few = identify_detail::identifyFewStars(ctx, *solver_);
    ctx.verify_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - ts).count();
    ctx.hypotheses = few.magnitude_ok;
    ctx.any_hypothesis = few.any_candidate;
    ctx.solved = few.solved;
    (few.solved ? ctx.accepted : ctx.best_rejected) = few.result;
    if (!few.solved) ctx.best_rejected.reason = few.reason;
    res.algorithm = name() + "+magnitudes";
    return finishWith(ctx);
  }
  if (n < minStars() || n_obs < options_.verify.min_matches) {
    res.status = IdentifyStatus::TooFewStars;
    res.reason = std::to_string(obs.size()) + " stars observed, " + name() + " needs at least " +
                 std::to_string(starsNeeded()) +
                 (n_obs >= 2 && n_obs <= 3
                      ? " (2 or 3 stars: the magnitude tie-break, magnitude_sigma > 0)"
                      : "");
    return finish();
  }
  for (auto& l : sc.lists) l.reset(db.stars().size());
  for (auto& c : sc.counters) c.reset(db.stars().size());

  VerifyOptions vopt = options_.verify;
  vopt.scale_tolerance = std::max(vopt.scale_tolerance, options_.scale_tolerance);
  const Verifier verifier(db, camera, *solver_, vopt);
  SearchContext ctx(obs, db, camera, options_, verifier, n, sc.lists, sc.counters);
  doIdentify(ctx);
  // Bright false stars (or missing catalog stars) can spoil every pattern among the
  // brightest few: search once more over more stars before giving up.
  const int n_retry = std::min<int>(static_cast<int>(obs.size()), options_.max_stars_retry);
  if (!ctx.solved && n_retry > n && ctx.hypotheses < options_.max_verifications) {
    SearchContext wide(obs, db, camera, options_, verifier, n_retry, sc.lists, sc.counters);
    wide.addAttitudes(ctx.attitudesExamined());
    wide.hypotheses = ctx.hypotheses;
    wide.verify_seconds = ctx.verify_seconds;
    wide.any_hypothesis = ctx.any_hypothesis;
    wide.best_rejected = ctx.best_rejected;
    doIdentify(wide);
    res.stars_used = n_retry;
    return finishWith(wide);
  }
  return finishWith(ctx);
}

int StarIdentifier::starsNeeded() const {
  return std::max(minStars(), options_.verify.min_matches);
}

IdentifyResult StarIdentifier::finishResult(SearchContext& ctx, IdentifyResult res,
                                            std::chrono::steady_clock::time_point t0) const {
  res.hypotheses_tried = ctx.hypotheses;
  res.attitudes_examined = ctx.attitudesExamined();
  res.timing.verify_ms = ctx.verify_seconds * 1e3;
  const VerificationResult& v = ctx.solved ? ctx.accepted : ctx.best_rejected;
  if (ctx.solved) {
    res.status = IdentifyStatus::Solved;
  } else if (ctx.any_hypothesis) {
    res.status = IdentifyStatus::Rejected;
    res.reason = "no hypothesis passed verification (" + std::to_string(ctx.hypotheses) +
                 " tried; best: " + v.reason + ")";
  } else {
    res.status = IdentifyStatus::NoMatch;
    res.reason = "no catalog pattern matches the " + std::to_string(ctx.n) + " brightest stars";
  }
  if (ctx.any_hypothesis) {
    res.q_ic = v.q_ic;
    res.cov_cam = v.cov_cam;
    res.matches = v.matches;
    res.false_match_probability = v.false_match_probability;
    res.rms_residual = v.rms_residual;
    res.rms_residual_px = v.rms_residual_px;
  }
  if (!ctx.solved) {
    // Never hand out an unverified attitude as if it were one.
    res.matches.clear();
  }
  res.timing.total_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  res.timing.pattern_ms = std::max(0.0, res.timing.total_ms - res.timing.verify_ms);
  return res;
}

}  // namespace st
