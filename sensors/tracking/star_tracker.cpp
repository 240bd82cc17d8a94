#include "sensors/tracking/star_tracker.hpp"

#include "sensors/identify/plate_solve.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "common/attitude.hpp"
#include "common/conventions.hpp"
#include "sensors/attitude/drop_worst.hpp"
#include "sensors/camera/jacobians.hpp"
#include "sensors/detect/star_detector.hpp"
#include "sensors/detect/streaks.hpp"
#include "sensors/identify/fov_search.hpp"
#include "sensors/identify/star_observation.hpp"
#include "sensors/tracking/observer_aberration.hpp"

namespace st {

namespace {

/// [px] A lost-in-space frame whose stars streak this far in its exposure is re-measured by
/// tracking (remeasureAsTracking): below 2 px a streak is within a PSF's width of round.
constexpr double kStreakedPx = 2.0;

using Clock = std::chrono::steady_clock;
double seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

/// Validated, with the detector judging blob shapes in the camera's pixel geometry (binned
/// rows: fy = fx / 2).
TrackerOptions forCamera(TrackerOptions o, const CameraModel& camera) {
  o.validate();
  o.detect.pixel_aspect = camera.pixelAspect();
  return o;
}

RecursiveIdOptions recursiveIdOptions(const TrackerOptions& o) {
  RecursiveIdOptions r;
  r.max_stars = o.max_tracked_stars;
  r.min_stars = o.min_tracked_stars;
  r.drop_saturated = o.drop_saturated;
  r.gate_sigma = o.gate_sigma;
  r.edge_margin_px = o.edge_margin_px;
  r.blend_separation_px = o.blend_separation_px;
  r.screen_pull_sigma = o.screen_pull_sigma;
  r.centroid_sigma_px = std::max(o.min_sigma_px, 0.1);
  r.exposure_s = o.exposure_s;
  r.detect = o.detect;
  return r;
}

FramePredictorOptions predictorOptions(const TrackerOptions& o) {
  return {o.frame_to_frame, o.max_propagation_s, o.accel_sigma, o.gyro_sigma, o.exposure_s};
}

/// [px] a centroid's own 1-sigma per axis (its covariance's mean variance), without the
/// model-error term: the online camera fit estimates that term from these.
double centroidSigmaPx(const Centroid& c) { return std::sqrt(std::max(0.0, 0.5 * c.cov_px.trace())); }

FrameFailure failureOf(IdentifyStatus s) {
  switch (s) {
    case IdentifyStatus::TooFewStars:
      return FrameFailure::kTooFewStars;
    case IdentifyStatus::Rejected:
      return FrameFailure::kRejected;
    case IdentifyStatus::NoMatch:
    case IdentifyStatus::Solved:
      break;
  }
  return FrameFailure::kNoMatch;
}

}  // namespace

StarTracker::StarTracker(const StarDatabase& db, const CameraModel& camera,
                         TrackerOptions options)
    : db_(db),
      camera_(camera),
      opts_(forCamera(std::move(options), camera)),
      detector_(opts_.detect),
      R_bc_(opts_.R_body_cam),
      identifier_(StarIdentifier::create(opts_.lis_algorithm, opts_.identify)),
      solver_(WahbaSolver::create(opts_.solver)),
      recursive_(db_, camera_, recursiveIdOptions(opts_)),
      predictor_(predictorOptions(opts_)),
      loss_threshold_(opts_.loss_probability, 2 * opts_.max_tracked_stars - 3),
      consistency_threshold_(chiSquareQuantile(1.0 - opts_.consistency_probability, 3.0)),
      online_(camera, opts_.online_camera) {}

StarTracker::~StarTracker() = default;

void StarTracker::reset() {
  predictor_.reset();
  failed_frames_ = 0;
  lost_ = true;
}

void StarTracker::useCamera(const CameraModel& camera, double model_error_px) {
  camera_ = camera;  // recursive_ holds a reference to camera_
  model_error_px_ = model_error_px;
  recursive_.cameraChanged(model_error_px);
}

void StarTracker::learnCamera(const Quat& q_ic, FrameStars stars, FrameResult& out) {
  stars.q_ic = q_ic;
  if (auto up = online_.addVerifiedFrame(camera_, std::move(stars))) {
    useCamera(up->fit.camera, up->model_error_px);
    out.camera_updated = true;
  }
}

void StarTracker::acceptLostInSpace(const std::optional<Vec3>& rate_cam, CameraFix& fix,
                                    FrameResult& out) {
  predictor_.correctForAcceleration(rate_cam, fix);
  setAttitude(out, fix);
  out.mode = StarTrackerMode::kLostInSpace;
  failed_frames_ = 0;
  lost_ = false;
  predictor_.addLostInSpaceFix(fix);
}

Vec3 StarTracker::referenceDirection(uint32_t star_index) const {
  const Vec3& u = db_.stars()[star_index].u_i;
  return velocity_ ? applyAberration(u, *velocity_) : u;
}

void StarTracker::setAttitude(FrameResult& out, const CameraFix& fix) const {
  // q_ib = q_ic (x) q_cb; dtheta_body = R_bc dtheta_cam.
  out.q_ib = canonical(fix.q_ic * Quat(R_bc_.transpose()));
  out.cov_body = R_bc_ * fix.cov_cam * R_bc_.transpose();
}

FrameResult StarTracker::process(const cv::Mat& image, double t_s, const FrameInputs& in) {
  const auto t0 = Clock::now();
  FrameResult out;
  out.R_body_cam = R_bc_;
  if (in.force_lost_in_space) reset();
  velocity_.reset();
  if (in.observer_velocity_km_s && in.observer_velocity_km_s->allFinite())
    velocity_ = in.observer_velocity_km_s;
  // The measured body rate in the camera frame: the external prediction's, else the gyro's.
  const Mat3 R_cb = R_bc_.transpose();
  std::optional<Vec3> rate_cam;
  if (in.rate_body) rate_cam = R_cb * *in.rate_body;
  std::optional<CameraPrediction> external;
  if (in.prediction) {
    // Body -> camera: q_ic = q_ib (x) q_bc, dtheta_cam = R_cb dtheta_body.
    const CameraPrediction p{canonical(in.prediction->q_ib * Quat(R_bc_)),
                             R_cb * in.prediction->cov_body * R_cb.transpose(),
                             R_cb * in.prediction->rate_body};
    // A prediction whose windows would have to be wider than the largest one cannot place
    // them (the gyroless filter before its second fix, a long coast): the frame is solved
    // lost-in-space instead, with the predicted rate only if it is known to a PSF over the
    // exposure, else from the streaks' shapes.
    const double psf = opts_.detect.psfSigmaGuess();
    const double half = opts_.detect.window_sigmas * sigmaAtCentrePx(p.cov_cam) + 3.0 * psf;
    const Mat3 cov_rate_cam = R_cb * in.prediction->cov_rate_body * R_cb.transpose();
    if (half <= opts_.detect.max_window_half_px) {
      external = p;
      rate_cam = p.rate_cam;
    } else if (sigmaAtCentrePx(cov_rate_cam) * opts_.exposure_s <= psf) {
      rate_cam = p.rate_cam;
    } else {
      rate_cam.reset();
    }
  }
  PredictionSource source = PredictionSource::kNone;
  std::optional<CameraPrediction> pred;
  if (!lost_) pred = predictor_.predict(t_s, external, rate_cam, &source);

  CameraFix fix;
  fix.t_s = t_s;
  if (pred) {
    out.prediction = source;
    if (track(image, *pred, source, out, fix)) {
      predictor_.correctForAcceleration(rate_cam, fix);
      setAttitude(out, fix);
      out.mode = StarTrackerMode::kTracking;
      failed_frames_ = 0;
      predictor_.addTrackingFix(fix);
    } else if ((source == PredictionSource::kRateMatch || opts_.reacquire_in_frame) &&
               (out.failure == FrameFailure::kTooFewInGate ||
                out.failure == FrameFailure::kTooFewPredicted)) {
      // Re-acquisition: the stars are not where they were going: the scene changed (an
      // unrelated frame, a slew nothing saw). Waiting for more failures would only lose
      // frames; the same frame is solved lost-in-space, within its budget. When that fails
      // too, a prediction of our own fixes is dropped (nothing else vouches for it), a gyro's
      // or a filter's stays for max_failed_frames (a blinded frame is a transient).
      const std::string why = out.detail;
      const bool own = source == PredictionSource::kRateMatch;
      if (own) reset();
      FrameResult lis;
      lis.R_body_cam = R_bc_;
      CameraFix lis_fix;
      lis_fix.t_s = t_s;
      if (lostInSpace(image, rate_cam, lis, lis_fix, opts_.reacquire_budget_s)) {
        reset();
        out = std::move(lis);
        fix = lis_fix;
        acceptLostInSpace(rate_cam, fix, out);
        out.detail = why + "; " + kReacquiredNote + (out.detail.empty() ? "" : ": " + out.detail);
        out.fell_back_to_lost_in_space = true;
      } else if (own) {
        out = std::move(lis);
        out.detail = why + "; " + kReacquiredNote + ": " + out.detail;
        out.fell_back_to_lost_in_space = true;
      } else {
        out.detail = why + "; " + kReacquiredNote + " failed too: " + lis.detail;
        if (++failed_frames_ >= opts_.max_failed_frames) {
          out.detail += "; " + std::to_string(failed_frames_) + " failed frames: back to lost-in-space";
          out.fell_back_to_lost_in_space = true;
          reset();
        }
      }
    } else if (++failed_frames_ >= opts_.max_failed_frames) {
      out.detail += "; " + std::to_string(failed_frames_) + " failed frames: back to lost-in-space";
      out.fell_back_to_lost_in_space = true;
      reset();
    }
  } else if (lostInSpace(image, rate_cam, out, fix)) {
    // No usable prediction: lost-in-space. The previous fix stays as the rate partner only if
    // it is recent enough to be the frame before.
    acceptLostInSpace(rate_cam, fix, out);
  } else {
    reset();
  }
  predictor_.recordRate(t_s, rate_cam);
  if (out.hasAttitude()) {
    RateFrame cur = RateFrame::of(t_s, out.stars, fix.cov_cam);
    if (rate_prev_ && t_s - rate_prev_->t_s <= opts_.max_propagation_s)
      out.rate = measureFrameRate(*rate_prev_, cur, R_bc_);
    rate_prev_ = std::move(cur);
  }
  out.model_error_px = model_error_px_;
  out.timings.total = seconds(t0, Clock::now());
  return out;
}

std::optional<Vec3> StarTracker::measureStreaksOf(const cv::Mat& image,
                                                  const std::optional<Vec3>& rate_cam,
                                                  std::vector<Centroid>& stars) {
  if (rate_cam && opts_.exposure_s > 0) {
    measureStreaks(
        image,
        [&](const Vec2& px) -> Vec2 {
          return attitudeJacobian(camera_, camera_.pixelToVector(px)) * *rate_cam *
                 opts_.exposure_s;
        },
        detector_, stars);
    return rate_cam;
  }
  const auto blur = streakFromShapes(stars, opts_.detect);
  if (!blur) return std::nullopt;
  measureStreaks(image, [&](const Vec2&) { return *blur; }, detector_, stars);
  if (!(opts_.exposure_s > 0)) return std::nullopt;
  // The cross-boresight rate that draws this streak at the centre (least norm: no roll; the
  // streak's sign is unknown, and a streak's centroid does not depend on it).
  const Mat23 J = attitudeJacobian(camera_, camera_.pixelToVector(imageCentre()));
  return Vec3(J.transpose() * (J * J.transpose()).ldlt().solve(*blur) / opts_.exposure_s);
}

double StarTracker::sigmaAtCentrePx(const Mat3& cov_cam) const {
  const Mat23 J = attitudeJacobian(camera_, camera_.pixelToVector(imageCentre()));
  const Mat2 C = J * cov_cam * J.transpose();
  return std::sqrt(std::max(0.0, Eigen::SelfAdjointEigenSolver<Mat2>(C).eigenvalues().maxCoeff()));
}

Vec2 StarTracker::imageCentre() const {
  return Vec2(0.5 * (camera_.width() - 1), 0.5 * (camera_.height() - 1));
}

bool StarTracker::lostInSpace(const cv::Mat& image, const std::optional<Vec3>& rate_cam,
                              FrameResult& out, CameraFix& fix, double budget_s) {
  const auto t0 = Clock::now();
  SearchLimits limits;
  if (budget_s > 0)
    limits.deadline = t0 + std::chrono::duration_cast<Clock::duration>(
                               std::chrono::duration<double>(budget_s));
  detector_.detect(image, det_);  // built once: no validation or allocation per frame
  DetectionResult& det = det_;
  std::optional<Vec3> streak_rate;  // the gyro's rate, or one that draws the shapes' streak
  if (det.reason.empty()) streak_rate = measureStreaksOf(image, rate_cam, det.stars);
  out.timings.detect = seconds(t0, Clock::now());
  out.num_blobs = det.blobs_found;
  if (!det.reason.empty()) {
    out.failure = FrameFailure::kDetection;
    out.detail = "lost-in-space: detection: " + det.reason;
    return false;
  }
  // The camera file as it is (with the model-error term carried from earlier frames); when
  // that fails, healed within +-camera_heal_range (identify/camera_refine.hpp).
  // Healing searches several focal lengths: worth it until the camera has verified a fix,
  // not on every dark or blinded frame after that.
  CameraFitPolicy policy = CameraFitPolicy::fixed();
  if (opts_.camera_heal_range > 0 && !camera_verified_) {
    policy = CameraFitPolicy::cameraFile(camera_);
    policy.heal_range = opts_.camera_heal_range;
  }
  const double floor_px = std::hypot(opts_.min_sigma_px, model_error_px_);
  LostInSpaceCameras lis;
  lis.camera = camera_;
  lis.policy = policy;
  // The same driver as `solve` (identify/plate_solve.hpp), with the tracker's one camera and
  // the normal parity: a camera file's frame is a proper rotation of the sky.
  FovSearchResult found = st::lostInSpace(det.stars, camera_.width(), camera_.height(), db_,
                                      *identifier_, lis, floor_px, ParityChoice::Normal, limits)
                              .search;
  const IdentifyResult& res = found.result;
  const std::vector<StarObservation>& obs = found.obs;
  out.timings.identify = 1e-3 * res.timing.pattern_ms;
  out.timings.attitude = 1e-3 * res.timing.verify_ms;
  if (!res.solved()) {
    out.failure = failureOf(res.status);
    out.detail = std::string("lost-in-space: ") + toString(res.status) +
                 (res.reason.empty() ? "" : ": " + res.reason);
    return false;
  }
  if (found.healed && found.camera_fit) {
    // The file failed; the camera that solved is the one in force from now on.
    online_.adopt(*found.camera_fit);
    useCamera(found.camera, found.model_error_px);
    out.camera_updated = true;
    out.detail = "lost-in-space healed the camera: " +
                 describeDiscrepancy(*found.camera_fit, online_.fileCamera(), "the camera file");
  }
  camera_verified_ = true;
  // Identified and verified against the database's directions: turned onto the apparent ones
  // of this observer (observer_aberration.hpp).
  Quat q_ic = res.q_ic;
  if (velocity_) {
    std::vector<Vec3> u;
    std::vector<double> w;
    for (const StarMatch& m : res.matches) {
      u.push_back(db_.stars()[m.star_index].u_i);
      w.push_back(1.0 / (obs[m.obs_index].sigma * obs[m.obs_index].sigma));
    }
    q_ic = correctForAberration(q_ic, u, w, *velocity_);
  }
  const Mat3 R_ci = q_ic.toRotationMatrix().transpose();
  FrameStars learnt;
  for (const StarMatch& m : res.matches) {
    const StarObservation& o = obs[m.obs_index];
    const Vec3 r_i = referenceDirection(m.star_index);
    MatchedStar s;
    s.catalog_id = m.catalog_id;
    s.px = o.px;
    s.v_cam = o.v_cam;
    s.residual = angleBetween(o.v_cam, R_ci * r_i);
    out.stars.push_back(s);
    learnt.add(o.px, r_i, centroidSigmaPx(det.stars[m.obs_index]));
  }
  fix.q_ic = canonical(q_ic);
  fix.cov_cam = res.cov_cam;
  if (streak_rate && streakPx(*streak_rate) >= kStreakedPx &&
      remeasureAsTracking(image, *streak_rate, out, fix))
    return true;  // the tracking pass learnt the camera from its stars
  if (!found.healed) learnCamera(q_ic, std::move(learnt), out);
  return true;
}

double StarTracker::streakPx(const Vec3& rate_cam) const {
  return (attitudeJacobian(camera_, camera_.pixelToVector(imageCentre())) * rate_cam *
          opts_.exposure_s)
      .norm();
}

bool StarTracker::remeasureAsTracking(const cv::Mat& image, const Vec3& rate_cam, FrameResult& out,
                                      CameraFix& fix) {
  // The full-frame streak centroids' covariances are ~1.4x optimistic (measured by
  // LostInSpaceCovariance.StreakedFixesErrorsMatchTheirSigma); tracking's windows measure
  // every identified star along its predicted streak with a consistent covariance. So the
  // verified lost-in-space attitude predicts this same frame and tracking measures it; its
  // consistency test (chi2(3) against the lost-in-space fix) and residual test still apply,
  // and a frame tracking cannot confirm keeps the lost-in-space fix.
  const CameraPrediction pred{fix.q_ic, fix.cov_cam, rate_cam};
  FrameResult tracked;
  CameraFix tracked_fix;
  tracked_fix.t_s = fix.t_s;
  if (!track(image, pred, PredictionSource::kExternal, tracked, tracked_fix)) return false;
  out.stars = std::move(tracked.stars);
  out.timings.detect += tracked.timings.detect;
  out.timings.identify += tracked.timings.identify;
  out.timings.attitude += tracked.timings.attitude;
  out.camera_updated = out.camera_updated || tracked.camera_updated;
  fix.q_ic = tracked_fix.q_ic;
  fix.cov_cam = tracked_fix.cov_cam;
  return true;
}

bool StarTracker::track(const cv::Mat& image, const CameraPrediction& pred,
                        PredictionSource source, FrameResult& out, CameraFix& fix) {
  auto fail = [&](FrameFailure kind, const std::string& why) {
    out.failure = kind;
    out.detail = std::string("tracking (") + toString(source) + "): " + why;
    return false;
  };
  recursive_.identify(image, pred, rid_);
  out.timings.identify = rid_.identify_s;
  out.timings.detect = rid_.detect_s;
  out.num_blobs = rid_.with_centroid;
  if (rid_.status == RecursiveIdResult::Status::kTooFewPredicted) {
    return fail(FrameFailure::kTooFewPredicted, "only " + std::to_string(rid_.windows) +
                                                    " catalog stars predicted in the image");
  }
  const auto t3 = Clock::now();
  if (rid_.status == RecursiveIdResult::Status::kTooFewInGate) {
    out.timings.attitude = seconds(t3, Clock::now());
    return fail(FrameFailure::kTooFewInGate,
                std::to_string(rid_.stars.size()) + " of " + std::to_string(rid_.windows) +
                    " predicted stars found inside the gate (" +
                    std::to_string(rid_.with_centroid) + " windows with a centroid)");
  }
  const std::optional<Failure> failure = solveTracked(pred, out, fix);
  out.timings.attitude = seconds(t3, Clock::now());
  if (failure) return fail(failure->kind, failure->detail);
  return true;
}

std::optional<StarTracker::Failure> StarTracker::solveTracked(const CameraPrediction& pred,
                                                              FrameResult& out,
                                                              CameraFix& fix) {
  // Every centroid's covariance + the camera-model error term (in quadrature).
  const double floor_px = std::hypot(opts_.tracking_min_sigma_px, model_error_px_);
  sobs_ = toStarObservations(rid_.stars, camera_, opts_.tracking_min_sigma_px, model_error_px_);
  const std::size_t n = sobs_.size();
  vobs_.resize(n);
  pix_.resize(n);
  keep_.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3 r_i = referenceDirection(rid_.star_index[k]);
    vobs_[k] = {sobs_[k].v_cam, r_i, sobs_[k].sigma};
    pix_[k] = {rid_.stars[k].px, rid_.stars[k].cov_px, r_i};
    keep_[k] = k;
  }
  // QUEST (isotropic sigmas) is the start of the pixel refinement (full covariances).
  std::optional<Failure> failure;
  PixelRefinement ref;
  auto solve = [&]() {
    const WahbaSolution sol = solver_->solve(vobs_);  // camera frame: q_ib here is q_ic
    if (!sol.ok) {
      failure = Failure{FrameFailure::kSolver, "solver: " + sol.reason};
      return false;
    }
    ref = refineInPixels(camera_, pix_, sol.q_ib, floor_px, e2_);
    if (!ref.ok) failure = Failure{FrameFailure::kSolver, ref.reason};
    return ref.ok;
  };
  // Loss test: sum d^T C^-1 d ~ chi2(2n - 3) (2 dof per star, 3 for the attitude).
  auto judge = [&]() -> DropWorstVerdict {
    const int dof = 2 * static_cast<int>(keep_.size()) - 3;
    if (ref.chi2 <= loss_threshold_(dof)) return {true, 0};
    return {false, std::size_t(std::max_element(e2_.begin(), e2_.end()) - e2_.begin())};
  };
  auto drop_and_resolve = [&](std::size_t worst) {
    vobs_.erase(vobs_.begin() + long(worst));
    pix_.erase(pix_.begin() + long(worst));
    keep_.erase(keep_.begin() + long(worst));
    return solve();
  };
  if (!solve()) return failure;
  const std::size_t min_keep = static_cast<std::size_t>(opts_.min_tracked_stars);
  const DropWorstOutcome outcome = dropWorstWhileFailing(n, min_keep, judge, drop_and_resolve);
  if (outcome == DropWorstOutcome::kSolverFailed) return failure;
  if (outcome == DropWorstOutcome::kTooFew) {
    return Failure{FrameFailure::kResiduals, "residual chi2 " + std::to_string(ref.chi2) +
                                                 " too large for " +
                                                 std::to_string(keep_.size()) + " stars"};
  }
  // Both attitudes are the camera's: the innovation is camera-frame.
  const Vec3 innov = quatLog(pred.q_ic.conjugate() * ref.q_ic);
  const Mat3 S = pred.cov_cam + ref.cov_cam;
  const double m2 = innov.dot(S.ldlt().solve(innov));
  if (!(m2 <= consistency_threshold_)) {
    return Failure{FrameFailure::kInconsistentPrediction,
                   "solution " + std::to_string(rad2arcsec(innov.norm())) +
                       " arcsec from the prediction (chi2(3) = " + std::to_string(m2) + ")"};
  }
  const Mat3 R_ci = ref.q_ic.toRotationMatrix().transpose();
  for (std::size_t j = 0; j < keep_.size(); ++j) {
    const std::size_t k = keep_[j];
    MatchedStar s;
    s.catalog_id = db_.stars()[rid_.star_index[k]].id;
    s.px = sobs_[k].px;
    s.v_cam = sobs_[k].v_cam;
    s.residual = angleBetween(vobs_[j].b, R_ci * vobs_[j].r);
    out.stars.push_back(s);
  }
  fix.q_ic = ref.q_ic;
  fix.cov_cam = ref.cov_cam;
  if (opts_.online_camera.enabled) {
    FrameStars learnt;
    for (std::size_t k : keep_)
      learnt.add(rid_.stars[k].px, referenceDirection(rid_.star_index[k]),
                 std::hypot(centroidSigmaPx(rid_.stars[k]), opts_.tracking_min_sigma_px));
    learnCamera(ref.q_ic, std::move(learnt), out);
  }
  return std::nullopt;
}

}  // namespace st
