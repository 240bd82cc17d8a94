#include "sensors/identify/camera_refine.hpp"

#include <algorithm>
#include <cmath>

#include "sensors/identify/fov_search.hpp"
#include "sensors/identify/verify.hpp"

namespace st {

CameraFitPolicy CameraFitPolicy::fixed() { return {}; }

CameraFitPolicy CameraFitPolicy::approximateFov(double scale_tolerance, double pixel_aspect) {
  CameraFitPolicy p;
  p.scale_tolerance = scale_tolerance;
  p.fit_focal = true;
  p.fit_aspect = !hasSquarePixels(pixel_aspect);
  p.radial_terms = 2;
  return p;
}

CameraFitPolicy CameraFitPolicy::cameraFile(const CameraModel& cam) {
  CameraFitPolicy p;
  p.fit_focal = true;
  p.fit_aspect = !hasSquarePixels(cam.pixelAspect());
  p.radial_terms = 2;
  // A datasheet focal length is good to 1-2 %; a star-tracker lens's radial terms are below
  // ~0.5 in normalised units. Both are priors, not bounds: the stars overrule them.
  p.prior = CameraPrior::around(cam, 0.05, 0, 0.5);
  p.heal_range = 0.05;
  return p;
}

FrameStars frameStarsOf(const std::vector<StarObservation>& obs, const IdentifyResult& r,
                        const StarDatabase& db, const CameraModel& cam) {
  FrameStars f;
  f.q_ic = r.q_ic;
  for (const StarMatch& m : r.matches)
    f.add(obs[m.obs_index].px, db.stars()[m.star_index].u_i,
          obs[m.obs_index].sigma / cam.pixelScale());
  return f;
}

CameraFitResult fitCameraToMatches(const CameraModel& cam, const std::vector<StarObservation>& obs,
                                   const IdentifyResult& r, const StarDatabase& db,
                                   const CameraFitPolicy& policy) {
  return fitCameraToStars(cam, frameStarsOf(obs, r, db, cam), policy);
}

CameraFitResult fitCameraToStars(const CameraModel& cam, const FrameStars& stars,
                                 const CameraFitPolicy& policy) {
  CameraFitSpec spec;
  spec.focal = policy.fit_focal;
  spec.aspect = policy.fit_focal && policy.fit_aspect;
  spec.radial_terms = policy.radial_terms;
  // The nested models (no radial term, k1, k1 + k2) are relative to the reference terms (the
  // camera file's, else none), not to whatever an earlier round fitted: otherwise terms once
  // fitted would stay whether or not the stars still support them.
  CameraParams start = cameraParams(cam);
  if (policy.radial_terms > 0) {
    start[kK1] = policy.prior ? policy.prior->mean[kK1] : 0.0;
    start[kK2] = policy.prior ? policy.prior->mean[kK2] : 0.0;
  }
  const CameraModel from = withCameraParams(cam, start);
  // A star matched wrongly (or a blend) must not bend the lens: 5-sigma outliers are left out.
  CameraFitOptions options;
  options.outlier_sigma = 5;
  return fitCameraChoosingRadial(from, {stars}, spec, policy.prior ? &*policy.prior : nullptr,
                                 options);
}

RefinedCandidate refineFromCandidate(const std::vector<Centroid>& centroids,
                                     const CameraModel& cam, std::vector<StarObservation> obs,
                                     IdentifyResult candidate, const StarDatabase& db,
                                     const IdentifyOptions& id_options,
                                     const CameraFitPolicy& policy, double min_sigma_px) {
  RefinedCandidate out{std::move(candidate), cam, std::move(obs), std::nullopt};
  const auto solver = WahbaSolver::create(id_options.solver);
  for (int round = 0; round < 5 && solver; ++round) {
    CameraFitResult fit = fitCameraToMatches(out.camera, out.obs, out.result, db, policy);
    if (!fit.ok) break;
    std::vector<StarObservation> obs2 = toStarObservations(centroids, fit.camera, min_sigma_px);
    VerifyOptions vo = id_options.verify;
    // What the fit leaves uncertain widens the gates like the FOV search's scale slack does.
    vo.scale_tolerance = std::max(1e-3, 3 * fit.sigma(kFx) / fit.theta[kFx]);
    vo.false_match_threshold = std::max(vo.false_match_threshold, kCandidateFalseMatchThreshold);
    const Verifier verifier(db, fit.camera, *solver, vo);
    const VerificationResult v = verifier.verifySeeds(
        obs2, out.result.matches, std::max(1.0, out.result.attitudes_examined));
    const bool grew = v.accepted && v.matches.size() > out.result.matches.size();
    out.camera = fit.camera;
    out.obs = std::move(obs2);
    out.fit = std::move(fit);
    if (!grew) break;
    out.result.matches = v.matches;
    out.result.q_ic = v.q_ic;
  }
  return out;
}

}  // namespace st
