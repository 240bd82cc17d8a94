#include "sensors/identify/fov_search.hpp"

#include <chrono>
#include <algorithm>
#include <cmath>
#include <cstdio>

namespace st {

std::vector<double> fovSearchGrid(double min_hfov, double max_hfov, double s) {
  std::vector<double> out;
  const double ratio = (1 + s) / (1 - s);
  for (double f = min_hfov * (1 + s); f <= max_hfov * ratio; f *= ratio) out.push_back(f);
  return out;
}

namespace {
/// A verified solution the limits refuse becomes a rejection with their reason.
FovSearchResult applyRefusal(FovSearchResult out, const SearchLimits& limits) {
  if (!out.result.solved() || !limits.refuse) return out;
  const std::string why = limits.refuse(out.result);
  if (!why.empty()) {
    out.result.status = IdentifyStatus::Rejected;
    out.result.reason = why;
    out.refused = why;
  }
  return out;
}
}  // namespace

namespace {

/// One identification with `slack` (relative focal-length tolerance). A candidate pass (slack
/// before a refit) has wide gates, so even a correct match has a large false-match
/// probability: it only proposes (relaxed threshold); the answer is the strict
/// identification with the fitted camera.
IdentifyResult identifyWith(StarIdentifier& identifier, const std::vector<StarObservation>& obs,
                            const StarDatabase& db, const CameraModel& cam, double slack,
                            bool candidate) {
  const IdentifyOptions saved = identifier.options();
  identifier.mutableOptions().scale_tolerance = slack;
  if (candidate)
    identifier.mutableOptions().verify.false_match_threshold =
        std::max(saved.verify.false_match_threshold, kCandidateFalseMatchThreshold);
  IdentifyResult r = identifier.identify(obs, db, cam);
  identifier.mutableOptions() = saved;
  return r;
}

/// The centroid floor of a candidate pass: its camera is approximate by construction, so its
/// model error (pixels at the corners) dominates any centroid's noise.
constexpr double kCandidateSigmaFloorPx = 0.5;
/// The largest camera-model error term a strict identification takes: a camera worse than
/// this is not one a star tracker can verify against (and a wrong match's scatter is larger).
constexpr double kMaxModelErrorPx = 1.0;

/// Candidate (with slack when the policy refines) -> fit -> re-match rounds -> the strict
/// identification with the fitted camera, its centroid sigmas widened by what the fitted
/// camera leaves unexplained (the model-error term).
FovSearchResult candidateAndRefine(const std::vector<Centroid>& centroids, const CameraModel& cam,
                                   const StarDatabase& db, StarIdentifier& identifier,
                                   const CameraFitPolicy& policy, double slack,
                                   double min_sigma_px) {
  FovSearchResult out;
  out.camera = cam;
  const bool candidate_pass = policy.refines() && slack > 0;
  const double floor_px =
      candidate_pass ? std::max(min_sigma_px, kCandidateSigmaFloorPx) : min_sigma_px;
  out.obs = toStarObservations(centroids, cam, floor_px);
  out.result = identifyWith(identifier, out.obs, db, cam, slack, candidate_pass);
  if (!out.result.solved() || !policy.refines()) return out;
  RefinedCandidate rc = refineFromCandidate(centroids, cam, out.obs, out.result, db,
                                            identifier.options(), policy, floor_px);
  // The last fit once more with the strict centroid sigmas (the rounds' floor hides terms
  // the stars support); what it leaves unexplained is the model-error term.
  const FrameStars stars = frameStarsOf(toStarObservations(centroids, rc.camera, min_sigma_px),
                                        rc.result, db, rc.camera);
  CameraFitResult fit = fitCameraToStars(rc.camera, stars, policy);
  if (!fit.ok) {
    fit = fitCamera(rc.camera, {stars}, CameraFitSpec{false, false, false, 0});
    if (!fit.ok) {
      if (candidate_pass) {  // a candidate is never an answer
        out.result.status = IdentifyStatus::Rejected;
        out.result.reason = "candidate at the approximate focal length: " + fit.reason;
      }
      return out;
    }
  }
  const double model_px = std::min(kMaxModelErrorPx, modelErrorSigmaPx(fit, {stars}));
  std::vector<StarObservation> obs = toStarObservations(centroids, fit.camera, min_sigma_px, model_px);
  IdentifyResult strict = identifyWith(identifier, obs, db, fit.camera, 0, false);
  if (strict.solved()) {
    out.camera = fit.camera;
    out.obs = std::move(obs);
    out.result = std::move(strict);
    out.model_error_px = model_px;
  } else if (candidate_pass) {
    out.result = std::move(strict);
    out.result.reason = "candidate at the approximate focal length did not verify with the "
                        "fitted one: " + out.result.reason;
  }  // else the given camera's strict solution stands
  return out;
}

/// The fit of the final matches: focal length and distortion with their uncertainties, and
/// the model-error term, for the report (and a camera file's discrepancy).
void attachFit(FovSearchResult& out, const StarDatabase& db, const CameraFitPolicy& policy) {
  if (!out.result.solved() || !policy.refines()) return;
  CameraFitResult fit = fitCameraToMatches(out.camera, out.obs, out.result, db, policy);
  if (!fit.ok) return;
  out.camera_fit = std::move(fit);
}

/// Focal-length factors of the healing search: 1, then outwards in steps of 2 * step_slack
/// (ranges that touch), up to +-range.
std::vector<double> healFactors(double range, double step_slack) {
  std::vector<double> out = {1.0};
  const double step = (1 + step_slack) / (1 - step_slack);
  for (double f = step; f - 1 <= range + step_slack; f *= step)
    out.push_back(f), out.push_back(1 / f);
  return out;
}

// The healing grid's ranges touch at +-2 %; each try's slack reaches a quarter of a step into
// its neighbours' (a focal length on the border is then well inside one of them).
constexpr double kHealStep = 0.02, kHealSlack = 0.025;

}  // namespace

FovSearchResult identifyAndFit(const std::vector<Centroid>& centroids, const CameraModel& cam,
                               const StarDatabase& db, StarIdentifier& identifier,
                               const CameraFitPolicy& policy, double min_sigma_px,
                               const SearchLimits& limits) {
  FovSearchResult out;
  out.camera = cam;
  if (limits.expired()) {
    out.cpu_limit_reached = true;
    out.result.reason = kCpuLimitReason;
    return out;
  }
  if (policy.heal_range <= 0) {
    out = candidateAndRefine(centroids, cam, db, identifier, policy, policy.scale_tolerance,
                             min_sigma_px);
  } else {
    // A camera file: as it is first (the normal case costs nothing more), then healed.
    out = candidateAndRefine(centroids, cam, db, identifier, CameraFitPolicy::fixed(), 0,
                             min_sigma_px);
    const std::string as_is = out.result.reason;
    // Square pixels: fx and fy scaled together. Non-square (binned) ones: their aspect is
    // only nominal, so fx and fy are scaled apart, the pairs nearest the file's first.
    std::vector<std::pair<double, double>> factors;
    const std::vector<double> fs = healFactors(policy.heal_range, kHealStep);
    for (double fx : fs)
      for (double fy : policy.fit_aspect ? fs : std::vector<double>{fx}) factors.push_back({fx, fy});
    std::stable_sort(factors.begin(), factors.end(), [](const auto& a, const auto& b) {
      const auto d = [](const std::pair<double, double>& f) {
        return std::abs(std::log(f.first)) + std::abs(std::log(f.second));
      };
      return d(a) < d(b);
    });
    if (out.result.solved()) factors.clear();
    for (const auto& [fx, fy] : factors) {
      if (limits.expired()) break;
      const CameraModel scaled(cam.width(), cam.height(), cam.fx() * fx, cam.fy() * fy, cam.cx(),
                               cam.cy(), cam.distortion());
      FovSearchResult h =
          candidateAndRefine(centroids, scaled, db, identifier, policy, kHealSlack, min_sigma_px);
      if (h.result.solved()) {
        out = std::move(h);
        out.healed = true;
        break;
      }
    }
    if (!out.result.solved()) {
      char b[120];
      std::snprintf(b, sizeof b, "; nor with the focal length refined within +-%.0f %%",
                    100 * policy.heal_range);
      out.result.reason = as_is + b;
    }
  }
  attachFit(out, db, policy);
  return applyRefusal(std::move(out), limits);
}

FovSearchResult identifyUnknownFov(const std::vector<Centroid>& centroids, int width,
                                   int height, const StarDatabase& db,
                                   StarIdentifier& identifier,
                                   const std::vector<double>& hfov_grid,
                                   double scale_tolerance, double min_sigma_px,
                                   const SearchLimits& limits, double pixel_aspect) {
  const auto t0 = std::chrono::steady_clock::now();
  FovSearchResult out;
  for (double hfov : hfov_grid) {
    if (limits.expired()) {
      out.cpu_limit_reached = true;
      break;
    }
    // The database must hold pairs across the whole image of this FOV.
    const CameraModel cam = CameraModel::fromFov(width, height, hfov, pixel_aspect);
    if (2 * cam.halfDiagonalFov() * (1 - scale_tolerance) > db.params().max_pair_angle) break;
    ++out.fovs_tried;
    FovSearchResult r =
        identifyAndFit(centroids, cam, db, identifier,
                       CameraFitPolicy::approximateFov(scale_tolerance, pixel_aspect),
                       min_sigma_px, limits);
    const bool solved = r.result.solved();
    out.cpu_limit_reached = r.cpu_limit_reached;
    if (!r.refused.empty()) out.refused = r.refused;
    if (solved || out.fovs_tried == 1) {
      const int tried = out.fovs_tried;
      std::string refused = std::move(out.refused);
      out = std::move(r);
      out.fovs_tried = tried;
      if (out.refused.empty()) out.refused = std::move(refused);
    }
    if (solved || out.cpu_limit_reached) break;
  }
  if (out.cpu_limit_reached && !out.result.solved())
    out.result.reason = std::string(kCpuLimitReason) + " after " +
                        std::to_string(out.fovs_tried) + " of " +
                        std::to_string(hfov_grid.size()) + " fields of view";
  else if (!out.result.solved() && out.fovs_tried > 0)
    out.result.reason = "no field of view in the search range gave a verified match (" +
                        std::to_string(out.fovs_tried) + " tried)" +
                        (out.refused.empty() ? "" : "; last refused: " + out.refused);
  else if (out.fovs_tried == 0)
    out.result.reason = "database pairs too short for the FOV range";
  out.search_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace st
