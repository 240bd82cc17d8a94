#include "sensors/mrpt/star_tracker_pipeline.hpp"

#include <mrpt/system/datetime.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "sensors/detect/star_detector.hpp"
#include "sensors/identify/star_observation.hpp"

namespace st {

namespace {

using Clock = std::chrono::steady_clock;
double seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

/// Upper quantile of chi-square with `dof` degrees of freedom at tail probability `alpha`
/// (Wilson & Hilferty 1931 cube-root normal approximation; relative error < 1% for dof >= 1
/// at alpha >= 1e-6, ample for a gate).
double chiSquareUpper(double dof, double alpha) {
  // Standard normal upper quantile z(alpha) by Acklam-style rational approximation in the
  // tail (|error| < 5e-4 for alpha in [1e-9, 0.5]).
  const double t = std::sqrt(-2.0 * std::log(alpha));
  const double z = t - (2.515517 + 0.802853 * t + 0.010328 * t * t) /
                           (1.0 + 1.432788 * t + 0.189269 * t * t + 0.001308 * t * t * t);
  const double a = 2.0 / (9.0 * dof);
  const double c = 1.0 - a + z * std::sqrt(a);
  return dof * c * c * c;
}

/// d(pixel)/d(v_cam) (2x3) of the camera projection at v_cam: pixel Jacobian of the
/// normalised coordinates times d(x/z, y/z)/dv.
Eigen::Matrix<double, 2, 3> projectionJacobian(const CameraModel& cam, const Vec3& v) {
  Eigen::Matrix<double, 2, 3> n;
  const double iz = 1.0 / v.z();
  n << iz, 0, -v.x() * iz * iz, 0, iz, -v.y() * iz * iz;
  return cam.pixelJacobian(v) * n;
}

/// d(pixel)/d(dtheta) (2x3) of the image of direction v_cam under a small rotation dtheta of
/// the camera: v_true = v + [v]x dtheta. The same Jacobian maps a body rate to the image
/// velocity (v(tau) = v + [v]x omega tau), so H omega T is a star's blur.
Eigen::Matrix<double, 2, 3> attitudeJacobian(const CameraModel& cam, const Vec3& v) {
  return projectionJacobian(cam, v) * skew(v);
}

double angleBetween(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

/// Without a rate, the streak every star draws, from the blobs' own shapes: a rotation
/// across the boresight streaks all stars alike. A streak of length L along a PSF of sigma s
/// has second moments L^2/12 + s^2 along and s^2 across, so L = sqrt(12 (l1 - l2)). The
/// brightest elongated blobs are whole streaks (faint ones break into fragments): their
/// median length, and the mean of their axes (doubled angles: an axis has no sign), must
/// agree, or nothing is returned (a roll, a tumble, double stars).
std::optional<Vec2> streakFromShapes(const std::vector<Centroid>& stars,
                                     const DetectorOptions& opts) {
  constexpr int kUse = 5;              // brightest elongated blobs used
  constexpr double kMinCoherence = 0.9;  // resultant length of the doubled axis angles
  std::vector<double> lengths;
  double c2 = 0, s2 = 0;
  for (const Centroid& c : stars) {  // brightest first
    if (static_cast<int>(lengths.size()) >= kUse) break;
    if (!(c.flags & kElongated) || (c.flags & (kSaturated | kTouchesEdge))) continue;
    const double a = c.shape(0, 0), b = c.shape(1, 1), x = c.shape(0, 1);
    const double dd = std::sqrt(0.25 * (a - b) * (a - b) + x * x);
    lengths.push_back(std::sqrt(12.0 * 2.0 * dd));  // l1 - l2 = 2 dd
    const double twice = std::atan2(2.0 * x, a - b);  // twice the major axis angle
    c2 += std::cos(twice);
    s2 += std::sin(twice);
  }
  if (lengths.size() < 3) return std::nullopt;
  const double n = static_cast<double>(lengths.size());
  if (std::hypot(c2, s2) / n < kMinCoherence) return std::nullopt;
  std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
  const double len = lengths[lengths.size() / 2];
  const double psf = opts.psfSigmaGuess();
  if (len <= 2.0 * psf) return std::nullopt;
  const double angle = 0.5 * std::atan2(s2, c2);
  return Vec2(len * std::cos(angle), len * std::sin(angle));
}

}  // namespace

struct StarTrackerPipeline::Candidate {
  uint32_t star_index;
  Vec3 v_cam;                       // predicted direction, camera frame
  Vec2 px;                          // predicted pixel
  Eigen::Matrix<double, 2, 3> H = Eigen::Matrix<double, 2, 3>::Zero();  // d(px)/d(dtheta_cam)
  Mat2 cov_att_px = Mat2::Zero();                                       // H P H^T
};

void PipelineOptions::validate() const {
  auto bad = [](const std::string& key, const std::string& why) {
    throw InputError("star tracker pipeline option '" + key + "': " + why);
  };
  if (!(exposure_s >= 0)) bad("exposure_s", "must be >= 0");
  if (max_tracked_stars < 3) bad("max_tracked_stars", "must be >= 3");
  if (min_tracked_stars < 3) bad("min_tracked_stars", "must be >= 3 (a check needs > 2 stars)");
  if (!(gate_sigma > 0)) bad("gate_sigma", "must be > 0");
  if (!(loss_probability > 0 && loss_probability < 0.5)) bad("loss_probability", "in (0, 0.5)");
  if (!(consistency_probability > 0 && consistency_probability < 0.5)) {
    bad("consistency_probability", "in (0, 0.5)");
  }
  if (max_failed_frames < 1) bad("max_failed_frames", "must be >= 1");
  if (!(max_propagation_s > 0)) bad("max_propagation_s", "must be > 0");
  if (!(accel_sigma >= 0)) bad("accel_sigma", "must be >= 0");
  if (!(gyro_sigma >= 0)) bad("gyro_sigma", "must be >= 0");
  if (!(min_sigma_px > 0)) bad("min_sigma_px", "must be > 0");
  if (!(tracking_min_sigma_px > 0)) bad("tracking_min_sigma_px", "must be > 0");
  std::string err;
  if (!detect.isValid(&err)) bad("detect", err);
}

StarTrackerPipeline::StarTrackerPipeline(const StarDatabase& db, const CameraModel& camera,
                                         PipelineOptions options)
    : db_(db), camera_(camera), opts_(std::move(options)) {
  opts_.validate();
  std::string err;
  identifier_ = StarIdentifier::create(opts_.lis_algorithm, opts_.identify, &err);
  if (!identifier_) throw InputError("star tracker pipeline option 'lis_algorithm': " + err);
  solver_ = WahbaSolver::create(opts_.solver, &err);
  if (!solver_) throw InputError("star tracker pipeline option 'solver': " + err);
  const auto& R = opts_.sensor_pose.getRotationMatrix();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) R_bc_(r, c) = R(r, c);
  half_diagonal_fov_ = camera_.halfDiagonalFov();
}

StarTrackerPipeline::~StarTrackerPipeline() = default;

void StarTrackerPipeline::setPrediction(const AttitudePrediction& p) { external_ = p; }
void StarTrackerPipeline::setGyroRate(const Vec3& rate_body) { gyro_rate_body_ = rate_body; }

void StarTrackerPipeline::reset() {
  last_.reset();
  prev_.reset();
  external_.reset();
  gyro_rate_body_.reset();
  last_rate_.reset();
  failed_frames_ = 0;
  lost_ = true;
}

std::optional<StarTrackerPipeline::Prediction> StarTrackerPipeline::predictionFor(
    mrpt::Clock::time_point t, const std::optional<Vec3>& rate_cam) {
  // One-shot inputs: consumed by this frame whatever happens.
  const auto external = std::exchange(external_, std::nullopt);
  const bool gyro = std::exchange(gyro_rate_body_, std::nullopt).has_value();
  if (lost_) return std::nullopt;

  const Mat3 R_cb = R_bc_.transpose();
  if (external) {
    // Body -> camera: q_ic = q_ib (x) q_bc, dtheta_cam = R_cb dtheta_body.
    Prediction p;
    p.q_ic = canonical(external->q_ib * Quat(R_bc_));
    p.cov_cam = R_cb * external->cov_body * R_cb.transpose();
    p.rate_cam = *rate_cam;  // the external prediction's rate
    p.source = "external";
    return p;
  }
  if (!opts_.frame_to_frame || !last_) return std::nullopt;
  const double dt = mrpt::system::timeDifference(last_->t, t);
  if (dt < 0 || dt > opts_.max_propagation_s) return std::nullopt;

  Prediction p;
  Mat3 rate_term = Mat3::Zero();
  if (gyro) {
    p.rate_cam = *rate_cam;
    rate_term = std::pow(opts_.gyro_sigma * dt, 2) * Mat3::Identity();
    p.source = "gyro";
  } else if (prev_) {
    // Rate match (seed 004 §5.5.3): the rate of the last two attitudes, held constant.
    const double dt_prev = mrpt::system::timeDifference(prev_->t, last_->t);
    if (!(dt_prev > 0) || dt_prev > opts_.max_propagation_s) return std::nullopt;
    p.rate_cam = quatLog(prev_->q_ic.conjugate() * last_->q_ic) / dt_prev;
    // Extrapolated error e = dth_last (1 + k) - dth_prev k, k = dt / dt_prev; plus a constant
    // angular acceleration over the extrapolation: alpha (dt^2 + dt dt_prev) / 2 per axis.
    const double k = dt / dt_prev;
    const double acc = 0.5 * opts_.accel_sigma * (dt * dt + dt * dt_prev);
    rate_term = (2 * k + k * k) * last_->cov_cam + k * k * prev_->cov_cam +
                acc * acc * Mat3::Identity();
    p.source = "rate match";
  } else {
    return std::nullopt;  // one attitude and no rate: lost-in-space once more
  }
  const Mat3 dR = quatExp(p.rate_cam * dt).toRotationMatrix();
  p.q_ic = canonical(last_->q_ic * quatExp(p.rate_cam * dt));
  p.cov_cam = dR.transpose() * last_->cov_cam * dR + rate_term;
  return p;
}

void StarTrackerPipeline::setAttitude(CObservationStarTracker& out, const Quat& q_ic,
                                      const Mat3& cov_cam) const {
  // q_ib = q_ic (x) q_cb; dtheta_body = R_bc dtheta_cam.
  out.q_ib = canonical(q_ic * Quat(R_bc_.transpose()));
  out.cov_body = R_bc_ * cov_cam * R_bc_.transpose();
}

CObservationStarTracker::Ptr StarTrackerPipeline::process(const cv::Mat& image,
                                                          mrpt::Clock::time_point t) {
  const auto t0 = Clock::now();
  auto out = CObservationStarTracker::Create();
  out->timestamp = t;
  out->sensorLabel = opts_.sensor_label;
  out->sensor_pose = opts_.sensor_pose;

  // The measured body rate in the camera frame: the external prediction's, else the gyro's.
  std::optional<Vec3> rate_cam;
  if (gyro_rate_body_) rate_cam = R_bc_.transpose() * *gyro_rate_body_;
  if (external_) rate_cam = R_bc_.transpose() * external_->rate_body;
  const auto pred = predictionFor(t, rate_cam);
  Fix fix;
  if (pred) {
    if (track(image, *pred, *out, fix)) {
      correctForAcceleration(rate_cam, t, *out, fix);
      out->mode = StarTrackerMode::kTracking;
      failed_frames_ = 0;
      prev_ = last_;
      last_ = fix;
    } else {
      out->mode = StarTrackerMode::kFailed;
      if (++failed_frames_ >= opts_.max_failed_frames) {
        out->reason += "; " + std::to_string(failed_frames_) +
                       " failed frames: back to lost-in-space";
        reset();
      }
    }
  } else {
    // No usable prediction: lost-in-space. The previous fix stays as the rate partner only if
    // it is recent enough to be the frame before.
    if (lostInSpace(image, rate_cam, *out, fix)) {
      correctForAcceleration(rate_cam, t, *out, fix);
      out->mode = StarTrackerMode::kLostInSpace;
      failed_frames_ = 0;
      lost_ = false;
      if (last_ && mrpt::system::timeDifference(last_->t, t) <= opts_.max_propagation_s) {
        prev_ = last_;
      } else {
        prev_.reset();
      }
      last_ = fix;
    } else {
      out->mode = StarTrackerMode::kFailed;
      reset();
    }
  }
  if (rate_cam) {
    last_rate_ = TimedRate{t, *rate_cam};
  } else {
    last_rate_.reset();
  }
  out->timings.total = seconds(t0, Clock::now());
  return out;
}

void StarTrackerPipeline::correctForAcceleration(const std::optional<Vec3>& rate_cam,
                                                 mrpt::Clock::time_point t,
                                                 CObservationStarTracker& out, Fix& fix) {
  if (!rate_cam || !last_rate_ || !(opts_.exposure_s > 0)) return;
  const double dt = mrpt::system::timeDifference(last_rate_->t, t);
  if (!(dt > 0) || dt > opts_.max_propagation_s) return;
  // theta(tau) = w tau + a tau^2 / 2 about mid-exposure; its mean over the exposure T is
  // a T^2 / 24, the rotation of the fix (q_ic(mean) = q_ic(mid) Exp(a T^2 / 24)). Each rate
  // carries gyro_sigma, so a has 2 gyro_sigma^2 / dt^2 per axis.
  const Vec3 accel = (*rate_cam - last_rate_->rate_cam) / dt;
  // Only an acceleration the rates resolve (3 sigma of their noise) is corrected for: below
  // that the correction would be mostly noise, and the bias it removes is below the noise
  // of the rates too.
  const double accel_sigma = std::sqrt(2.0) * opts_.gyro_sigma / dt;
  if (accel.norm() < 3.0 * accel_sigma) return;
  const double k = opts_.exposure_s * opts_.exposure_s / 24.0;
  fix.q_ic = canonical(fix.q_ic * quatExp(-k * accel));
  fix.cov_cam += 2.0 * std::pow(k * opts_.gyro_sigma / dt, 2) * Mat3::Identity();
  setAttitude(out, fix.q_ic, fix.cov_cam);
}

void StarTrackerPipeline::measureStreaks(const cv::Mat& image,
                                         const std::function<Vec2(const Vec2&)>& blur_at,
                                         std::vector<Centroid>& stars) const {
  const double psf = opts_.detect.psfSigmaGuess();
  std::vector<PredictedStar> streaks;
  std::vector<std::size_t> index;
  for (std::size_t k = 0; k < stars.size(); ++k) {
    const Vec2 blur = blur_at(stars[k].px);
    if (blur.norm() <= 2.0 * psf) continue;
    // The centroid of a fragment lies on the streak, at most half its length from the
    // middle: the window (5 sigma + 3 psf + blur/2) then holds the whole streak.
    PredictedStar p;
    p.px = stars[k].px;
    p.cov_px = std::pow(0.25 * blur.norm(), 2) * Mat2::Identity();
    p.blur_px = blur;
    p.anchor_at_px = true;
    streaks.push_back(p);
    index.push_back(k);
  }
  if (streaks.empty()) return;
  const std::vector<WindowResult> found = centroidWindows(image, streaks, opts_.detect);
  const std::vector<Centroid> detected = stars;
  std::vector<bool> drop(stars.size(), false);
  for (std::size_t j = 0; j < found.size(); ++j) {
    if (!found[j].centroid) {
      drop[index[j]] = true;  // no streak around this blob (noise, a hot pixel)
      continue;
    }
    // A blob in the centroid window (half-size 2.5 psf + blur/2) off this streak's segment
    // is another star whose light pulls the CoG: the star is left out (a blend). Fragments
    // of the streak itself lie on the segment.
    const Vec2 c = found[j].centroid->px, b = streaks[j].blur_px;
    const Vec2 u = b.normalized();
    const double reach = 2.5 * psf + 0.5 * b.norm() + 3.0 * psf;
    for (const Centroid& o : detected) {
      const Vec2 d = o.px - c;
      if (d.cwiseAbs().maxCoeff() > reach) continue;
      const double along = std::abs(d.dot(u)), across = std::abs(u.x() * d.y() - u.y() * d.x());
      if (across > 3.0 * psf || along > 0.5 * b.norm() + 3.0 * psf) drop[index[j]] = true;
    }
    if (!drop[index[j]]) stars[index[j]] = *found[j].centroid;
  }
  // Fragments of one streak now share one centroid: keep the first (brightest) of each.
  std::vector<Centroid> kept;
  for (std::size_t k = 0; k < stars.size(); ++k) {
    if (drop[k]) continue;
    bool dup = false;
    for (const Centroid& o : kept)
      dup = dup || (o.px - stars[k].px).norm() < 2.0 * psf;
    if (!dup) kept.push_back(stars[k]);
  }
  stars = std::move(kept);
}

bool StarTrackerPipeline::lostInSpace(const cv::Mat& image, const std::optional<Vec3>& rate_cam,
                                      CObservationStarTracker& out, Fix& fix) {
  const auto t0 = Clock::now();
  DetectionResult det = detectStars(image, opts_.detect);
  if (det.reason.empty()) {
    if (rate_cam && opts_.exposure_s > 0) {
      measureStreaks(
          image,
          [&](const Vec2& px) -> Vec2 {
            const Vec3 v = camera_.pixelToVector(px);
            return attitudeJacobian(camera_, v) * *rate_cam * opts_.exposure_s;
          },
          det.stars);
    } else if (const auto blur = streakFromShapes(det.stars, opts_.detect)) {
      measureStreaks(image, [&](const Vec2&) { return *blur; }, det.stars);
    }
  }
  out.timings.detect = seconds(t0, Clock::now());
  out.num_blobs = det.blobs_found;
  if (!det.reason.empty()) {
    out.reason = "lost-in-space: detection: " + det.reason;
    return false;
  }
  const std::vector<StarObservation> obs =
      toStarObservations(det.stars, camera_, opts_.min_sigma_px);
  const IdentifyResult res = identifier_->identify(obs, db_, camera_);
  out.timings.identify = 1e-3 * res.timing.pattern_ms;
  out.timings.attitude = 1e-3 * res.timing.verify_ms;
  if (!res.solved()) {
    out.reason = std::string("lost-in-space: ") + toString(res.status) +
                 (res.reason.empty() ? "" : ": " + res.reason);
    return false;
  }
  const Mat3 R_ic = res.q_ib.toRotationMatrix();
  for (const StarMatch& m : res.matches) {
    const StarObservation& o = obs[m.obs_index];
    MatchedStar s;
    s.catalog_id = m.catalog_id;
    s.px = o.px;
    s.v_cam = o.v_cam;
    s.residual = angleBetween(o.v_cam, R_ic.transpose() * db_.stars()[m.star_index].u_i);
    out.stars.push_back(s);
  }
  setAttitude(out, res.q_ib, res.cov_body);
  fix = {out.timestamp, canonical(res.q_ib), res.cov_body};
  return true;
}

bool StarTrackerPipeline::track(const cv::Mat& image, const Prediction& pred,
                                CObservationStarTracker& out, Fix& fix) {
  const auto t0 = Clock::now();
  const Mat3 R_ic = pred.q_ic.toRotationMatrix();
  // sqrt(trace) bounds the largest 1-sigma of the attitude (cheaper than an eigen solve).
  const double att_sigma = std::sqrt(std::max(0.0, pred.cov_cam.trace()));

  // 1. Catalog stars expected in the image (seed 002: cone of the FOV + the attitude
  //    uncertainty), projected with the camera model.
  db_.coneQuery(R_ic.col(2), half_diagonal_fov_ + 3.0 * att_sigma, cone_);
  candidates_.clear();
  for (uint32_t i : cone_) {
    const Vec3 v = R_ic.transpose() * db_.stars()[i].u_i;
    if (v.z() <= 0) continue;
    const auto px = camera_.vectorToPixel(v);
    if (!px || !camera_.isPixelInImage(*px, 0.0)) continue;
    Candidate c;
    c.star_index = i;
    c.v_cam = v;
    c.px = *px;
    candidates_.push_back(c);
  }
  // 2. The brightest stars (cone order = brightest first) away from the border and from
  //    blends, each with its window.
  std::vector<PredictedStar> windows;
  std::vector<const Candidate*> windowed;
  const double blend2 = opts_.blend_separation_px * opts_.blend_separation_px;
  const double sigma_c2 = std::pow(std::max(opts_.min_sigma_px, 0.1), 2);
  // Blends: the centroid window of a star is a square of half-size 2.5 psf + blur/2 around
  // its image's middle (centroidWindows), and another star's light reaches 3 psf beyond its
  // own streak (o.px +- blur/2). A star is windowed only if no other catalog star's light
  // falls into its window: for a streak that is a box of ~(blur + 6 psf) around it, not a
  // fixed radius (streaks of neighbours overlap along the streak direction and pull the
  // centre of gravity by flux ratio x distance). PSF sigma as the detector assumes it.
  const double psf = opts_.detect.psfSigmaGuess();
  for (Candidate& c : candidates_) {
    if (int(windows.size()) >= opts_.max_tracked_stars) break;
    if (!camera_.isPixelInImage(c.px, opts_.edge_margin_px)) continue;
    // Error model: v_true = Exp(-dtheta) v = v + [v]x dtheta (R_true = R Exp(dtheta)).
    c.H = attitudeJacobian(camera_, c.v_cam);
    const Vec2 blur = c.H * pred.rate_cam * opts_.exposure_s;
    const double hc = std::ceil(2.5 * psf + 0.5 * blur.norm());
    const double reach_x = hc + 0.5 * std::abs(blur.x()) + 3.0 * psf;
    const double reach_y = hc + 0.5 * std::abs(blur.y()) + 3.0 * psf;
    bool blended = false;
    for (const Candidate& o : candidates_) {
      if (&o == &c) continue;
      const Vec2 d = o.px - c.px;
      if (d.squaredNorm() < blend2 || (std::abs(d.x()) < reach_x && std::abs(d.y()) < reach_y)) {
        blended = true;
        break;
      }
    }
    if (blended) continue;
    c.cov_att_px = c.H * pred.cov_cam * c.H.transpose();
    PredictedStar p;
    p.px = c.px;
    p.cov_px = c.cov_att_px + sigma_c2 * Mat2::Identity();
    p.blur_px = blur;
    windows.push_back(p);
    windowed.push_back(&c);
  }
  const auto t1 = Clock::now();
  if (int(windows.size()) < opts_.min_tracked_stars) {
    out.reason = "tracking (" + pred.source + "): only " + std::to_string(windows.size()) +
                 " catalog stars predicted in the image";
    out.timings.identify = seconds(t0, t1);
    return false;
  }

  // 3. Centroids in the windows only (seed 004 §4.2.3).
  const std::vector<WindowResult> found = centroidWindows(image, windows, opts_.detect);
  const auto t2 = Clock::now();
  out.timings.detect = seconds(t1, t2);

  // 4. Mahalanobis gate per star (seed 002 step 5: |d| < 3 sqrt(2) sigma).
  const double gate2 = opts_.gate_sigma * opts_.gate_sigma;
  std::vector<Centroid> gated;
  std::vector<const Candidate*> gated_cand;
  std::vector<double> gated_d2;
  int with_centroid = 0;
  for (std::size_t k = 0; k < found.size(); ++k) {
    if (!found[k].centroid) continue;
    ++with_centroid;
    const Centroid& cen = *found[k].centroid;
    const Vec2 d = cen.px - windowed[k]->px;
    const Mat2 S = windowed[k]->cov_att_px + cen.cov_px + sigma_c2 * Mat2::Identity();
    const double d2 = d.dot(S.ldlt().solve(d));
    if (!(d2 <= gate2)) continue;
    // Two windows that caught the same blob: keep the closer prediction.
    bool duplicate = false;
    for (std::size_t j = 0; j < gated.size(); ++j) {
      if ((gated[j].px - cen.px).squaredNorm() < 1.0) {
        duplicate = true;
        if (d2 < gated_d2[j]) {
          gated[j] = cen;
          gated_cand[j] = windowed[k];
          gated_d2[j] = d2;
        }
        break;
      }
    }
    if (duplicate) continue;
    gated.push_back(cen);
    gated_cand.push_back(windowed[k]);
    gated_d2.push_back(d2);
  }
  out.num_blobs = with_centroid;
  if (opts_.drop_saturated) {
    std::size_t unsaturated = 0;
    for (const Centroid& c : gated) unsaturated += !(c.flags & kSaturated);
    if (int(unsaturated) >= opts_.min_tracked_stars && unsaturated < gated.size()) {
      std::size_t w = 0;
      for (std::size_t k = 0; k < gated.size(); ++k) {
        if (gated[k].flags & kSaturated) continue;
        gated[w] = gated[k];
        gated_cand[w] = gated_cand[k];
        gated_d2[w] = gated_d2[k];
        ++w;
      }
      gated.resize(w);
      gated_cand.resize(w);
      gated_d2.resize(w);
    }
  }
  const auto t3 = Clock::now();
  out.timings.identify = seconds(t0, t1) + seconds(t2, t3);

  auto fail = [&](const std::string& why) {
    out.reason = "tracking (" + pred.source + "): " + why;
    out.timings.attitude = seconds(t3, Clock::now());
    return false;
  };
  if (int(gated.size()) < opts_.min_tracked_stars) {
    return fail(std::to_string(gated.size()) + " of " + std::to_string(windows.size()) +
                " predicted stars found inside the gate (" + std::to_string(with_centroid) +
                " windows with a centroid)");
  }

  // 5. Solve, then verify: loss chi-square (dropping the worst star while it fails) and
  //    consistency with the prediction.
  const double floor_px = opts_.tracking_min_sigma_px;
  const std::vector<StarObservation> sobs = toStarObservations(gated, camera_, floor_px);
  std::vector<VectorObservation> vobs(sobs.size());
  for (std::size_t k = 0; k < sobs.size(); ++k) {
    vobs[k] = {sobs[k].v_cam, db_.stars()[gated_cand[k]->star_index].u_i, sobs[k].sigma};
  }
  std::vector<std::size_t> keep(sobs.size());
  for (std::size_t k = 0; k < keep.size(); ++k) keep[k] = k;
  // Solve, then refine with the full covariances. QUEST weighs each star with one isotropic
  // sigma, but a streak's centroid error is several times larger along the streak than
  // across it, and all streaks of a frame are parallel: the isotropic model misstates the
  // attitude covariance (optimistic about the axis the streaks move along). Gauss-Newton on
  // the pixel residuals d_k = c_k - pi(R^T r_k) with their 2x2 covariances C_k, where
  // pi(R Exp(dth)^T r) = pi(R^T r) + H_k dth (H_k as for the windows):
  //   dth = N^-1 sum H^T C^-1 d,  N = sum H^T C^-1 H,  covariance of the solution N^-1
  // (the Fisher information of the pixel measurements). QUEST is the start; two steps
  // converge. The loss test is then sum d^T C^-1 d ~ chi2(2n - 3) (2 dof per star, 3 for the
  // attitude), the worst star removed while it fails.
  const Mat2 floor2 = floor_px * floor_px * Mat2::Identity();
  WahbaSolution sol;
  std::vector<double> e2(keep.size());
  for (;;) {
    sol = solver_->solve(vobs);
    if (!sol.ok) return fail("solver: " + sol.reason);
    double chi2 = 0;
    for (int it = 0; it < 3; ++it) {
      const Mat3 R = sol.q_ib.toRotationMatrix();
      Mat3 N = Mat3::Zero();
      Vec3 g = Vec3::Zero();
      chi2 = 0;
      for (std::size_t j = 0; j < keep.size(); ++j) {
        const std::size_t k = keep[j];
        const Vec3 v = R.transpose() * db_.stars()[gated_cand[k]->star_index].u_i;
        const auto px = camera_.vectorToPixel(v);
        if (!px) return fail("a matched star projects outside the camera");
        const Eigen::Matrix<double, 2, 3> H = attitudeJacobian(camera_, v);
        const Mat2 Ci = (gated[k].cov_px + floor2).inverse();
        const Vec2 d = gated[k].px - *px;
        N += H.transpose() * Ci * H;
        g += H.transpose() * Ci * d;
        e2[j] = d.dot(Ci * d);
        chi2 += e2[j];
      }
      if (it == 2) break;  // the last pass only evaluates the residuals
      const Eigen::LDLT<Mat3> ldlt(N);
      if (ldlt.info() != Eigen::Success || !(N.determinant() > 0)) {
        return fail("degenerate star geometry");
      }
      sol.q_ib = canonical(sol.q_ib * quatExp(ldlt.solve(g)));
      sol.cov_body = N.inverse();
    }
    const double n = double(keep.size());
    if (chi2 <= chiSquareUpper(2.0 * n - 3.0, opts_.loss_probability)) break;
    if (int(keep.size()) <= opts_.min_tracked_stars) {
      return fail("residual chi2 " + std::to_string(chi2) + " too large for " +
                  std::to_string(keep.size()) + " stars");
    }
    const std::size_t worst =
        std::size_t(std::max_element(e2.begin(), e2.begin() + long(keep.size())) - e2.begin());
    vobs.erase(vobs.begin() + long(worst));
    keep.erase(keep.begin() + long(worst));
  }
  const Vec3 innov = quatLog(pred.q_ic.conjugate() * sol.q_ib);
  const Mat3 Sinn = pred.cov_cam + sol.cov_body;
  const double m2 = innov.dot(Sinn.ldlt().solve(innov));
  if (!(m2 <= chiSquareUpper(3.0, opts_.consistency_probability))) {
    return fail("solution " + std::to_string(rad2arcsec(innov.norm())) +
                " arcsec from the prediction (chi2(3) = " + std::to_string(m2) + ")");
  }

  const Mat3 R_ic_sol = sol.q_ib.toRotationMatrix();
  for (std::size_t j = 0; j < keep.size(); ++j) {
    const std::size_t k = keep[j];
    MatchedStar s;
    s.catalog_id = db_.stars()[gated_cand[k]->star_index].id;
    s.px = sobs[k].px;
    s.v_cam = sobs[k].v_cam;
    s.residual = angleBetween(vobs[j].b, R_ic_sol.transpose() * vobs[j].r);
    out.stars.push_back(s);
  }
  setAttitude(out, sol.q_ib, sol.cov_body);
  fix = {out.timestamp, canonical(sol.q_ib), sol.cov_body};
  out.timings.attitude = seconds(t3, Clock::now());
  return true;
}

}  // namespace st
