#include "sensors/identify/fov_search.hpp"

#include <chrono>
#include <algorithm>
#include <cmath>

namespace st {

std::vector<double> fovSearchGrid(double min_hfov, double max_hfov, double s) {
  std::vector<double> out;
  const double ratio = (1 + s) / (1 - s);
  for (double f = min_hfov * (1 + s); f <= max_hfov * ratio; f *= ratio) out.push_back(f);
  return out;
}

CameraModel fitFocalLength(const CameraModel& cam, const std::vector<StarObservation>& obs,
                           const IdentifyResult& r, const StarDatabase& db) {
  if (r.matches.size() < 3) return cam;
  const Mat3 R_ci = r.q_ic.toRotationMatrix().transpose();
  const double a = cam.fy() / cam.fx();
  // p - c = f * (xn, a*yn)  =>  f = sum (p-c).(xn, a yn) / sum |(xn, a yn)|^2
  double num = 0, den = 0;
  for (const StarMatch& m : r.matches) {
    const Vec3 v = R_ci * db.stars()[m.star_index].u_i;
    const Vec2 xn(v.x() / v.z(), a * v.y() / v.z());
    const Vec2 d = obs[m.obs_index].px - Vec2(cam.cx(), cam.cy());
    num += d.dot(xn);
    den += xn.squaredNorm();
  }
  if (!(den > 0) || !(num > 0)) return cam;
  const double f = num / den;
  return CameraModel(cam.width(), cam.height(), f, a * f, cam.cx(), cam.cy(), cam.distortion());
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

FovSearchResult identifyAndFit(const std::vector<Centroid>& centroids, const CameraModel& cam,
                               const StarDatabase& db, StarIdentifier& identifier,
                               double scale_tolerance, bool fit_focal, double min_sigma_px,
                               const SearchLimits& limits) {
  FovSearchResult out;
  out.camera = cam;
  if (limits.expired()) {
    out.cpu_limit_reached = true;
    out.result.reason = kCpuLimitReason;
    return out;
  }
  const IdentifyOptions saved = identifier.options();
  // With scale slack the gates are wide, so the false-match probability of even a correct
  // match is large: the first pass only proposes a candidate (relaxed threshold); the answer
  // is the strict identification with the fitted focal length below.
  const bool candidate_pass = fit_focal && scale_tolerance > 0;
  identifier.mutableOptions().scale_tolerance = scale_tolerance;
  if (candidate_pass)
    identifier.mutableOptions().verify.false_match_threshold =
        std::max(saved.verify.false_match_threshold, kCandidateFalseMatchThreshold);
  out.obs = toStarObservations(centroids, cam, min_sigma_px);
  out.result = identifier.identify(out.obs, db, cam);
  identifier.mutableOptions() = saved;
  if (!out.result.solved() || !fit_focal) return applyRefusal(std::move(out), limits);
  // Refit the focal length and identify again without scale slack (two rounds: the first
  // attitude was fitted with the wrong scale).
  bool strict_solved = !candidate_pass;
  IdentifyResult last_failure;
  for (int round = 0; round < 2; ++round) {
    const CameraModel fitted = fitFocalLength(out.camera, out.obs, out.result, db);
    std::vector<StarObservation> obs = toStarObservations(centroids, fitted, min_sigma_px);
    IdentifyResult r = identifier.identify(obs, db, fitted);
    if (!r.solved()) {
      last_failure = std::move(r);
      break;
    }
    strict_solved = true;
    out.camera = fitted;
    out.obs = std::move(obs);
    out.result = std::move(r);
  }
  if (!strict_solved) {
    out.result = std::move(last_failure);
    out.result.reason = "candidate at the approximate focal length did not verify with the "
                        "fitted one: " + out.result.reason;
  }
  return applyRefusal(std::move(out), limits);
}

FovSearchResult identifyUnknownFov(const std::vector<Centroid>& centroids, int width,
                                   int height, const StarDatabase& db,
                                   StarIdentifier& identifier,
                                   const std::vector<double>& hfov_grid,
                                   double scale_tolerance, double min_sigma_px,
                                   const SearchLimits& limits) {
  const auto t0 = std::chrono::steady_clock::now();
  FovSearchResult out;
  for (double hfov : hfov_grid) {
    if (limits.expired()) {
      out.cpu_limit_reached = true;
      break;
    }
    // The database must hold pairs across the whole image of this FOV.
    const CameraModel cam = CameraModel::fromFov(width, height, hfov);
    if (2 * cam.halfDiagonalFov() * (1 - scale_tolerance) > db.params().max_pair_angle) break;
    ++out.fovs_tried;
    FovSearchResult r = identifyAndFit(centroids, cam, db, identifier, scale_tolerance, true,
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
