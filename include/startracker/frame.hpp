/// @file frame.hpp
/// The tracking stage's seam: what one frame needs from outside (FrameInputs) and what it
/// gives back (FrameResult). MRPT-free; the MRPT adapters (sensors/mrpt/) turn a FrameResult
/// into a CObservationStarTracker, the fusion loop (fusion/) builds the FrameInputs.
///
/// Frames (common/conventions.hpp): everything here is in the BODY frame given by the
/// tracker's camera mounting (identity: body = camera). Camera-frame quantities inside the
/// tracker are named `_ic` / `_cam`.
/// Time: seconds as double on the caller's monotonic scale (e.g. seconds from the first
/// observation of a run). The tracker only ever takes differences of these times.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "startracker/attitude.hpp"

namespace st {

/// An attitude prediction for a frame time, in the body frame (e.g. the filter's).
struct AttitudePrediction {
  Quat q_ib = Quat::Identity();
  Mat3 cov_body = Mat3::Identity();  ///< [rad^2]
  Vec3 rate_body = Vec3::Zero();     ///< [rad/s] body rate at the frame (blur, acceleration)
  /// [rad^2/s^2] covariance of rate_body: the gyroless filter's rate state; zero for a rate a
  /// gyro measured
  Mat3 cov_rate_body = Mat3::Zero();
};

/// Everything one frame takes from outside the tracker. All optional: with nothing, the
/// tracker predicts frame to frame from its own fixes, or runs lost-in-space.
struct FrameInputs {
  /// The filter's prediction at the frame time (takes precedence over `rate_body`).
  std::optional<AttitudePrediction> prediction;
  /// A measured body rate [rad/s] over the frame (a gyro without an attitude filter, or a
  /// filter not initialised yet): streak lengths, frame-to-frame propagation.
  std::optional<Vec3> rate_body;
  /// Forget the tracking state before this frame and run lost-in-space (the fusion loop's
  /// re-initialisation policy: its prediction was refused too often).
  bool force_lost_in_space = false;
  /// [km/s] The observer's velocity in the inertial frame whose aberration the star database
  /// does not hold (an orbit's, relative to the Earth's centre: the rawlog contract's
  /// VELOCITY). The fix is then the attitude against the stars' apparent directions for this
  /// observer (seed 003 "Aberration": up to 5.7" for a low orbit), not a rotation off by it.
  std::optional<Vec3> observer_velocity_km_s;
};

/// How the fix of a frame was obtained. Values are serialized (CObservationStarTracker).
enum class StarTrackerMode : uint8_t {
  kLostInSpace = 0,  ///< full-frame detection + lost-in-space identification
  kTracking = 1,     ///< predicted windows + recursive identification
  kFailed = 2,       ///< no attitude this frame (see FrameResult::failure)
};
/// "lost-in-space", "tracking", "failed".
const char* toString(StarTrackerMode mode);

/// Why a frame has no attitude. One enum for both modes, so callers count by value.
enum class FrameFailure : uint8_t {
  kNone = 0,
  kDetection,             ///< lost-in-space: detection found too little (see detail)
  kTooFewStars,           ///< lost-in-space: fewer stars than the identifier needs
  kNoMatch,               ///< lost-in-space: no catalog pattern fits
  kRejected,              ///< lost-in-space: every hypothesis failed verification
  kTooFewPredicted,       ///< tracking: too few catalog stars predicted in the image
  kTooFewInGate,          ///< tracking: too few predicted stars found inside the gate
  kSolver,                ///< the Wahba solver failed / degenerate star geometry
  kResiduals,             ///< the residual chi-square test failed down to the minimum stars
  kInconsistentPrediction,///< tracking: the solution contradicts the prediction
  kUnknown,               ///< a failure whose kind was not recorded (old rawlogs)
  kNoImage,               ///< the frame's image could not be loaded or was empty
  kFrozenImage,           ///< the image repeats the previous one pixel for pixel
  kClockRefused,          ///< stamped ahead of the gyro's timeline: cannot have been taken yet
  kLast = kClockRefused,  ///< the largest value (serialization range check)
};
/// A short stable name ("no-match", "too-few-in-gate", ...), for logs and counters.
const char* toString(FrameFailure f);

/// Where a tracking frame's prediction came from.
enum class PredictionSource : uint8_t { kNone = 0, kExternal, kGyro, kRateMatch };
const char* toString(PredictionSource s);

/// One identified star of the fix.
struct MatchedStar {
  uint32_t catalog_id = 0;      ///< HIP or HR number (catalog/star_catalog.hpp)
  Vec2 px = Vec2::Zero();       ///< [px] measured centroid
  Vec3 v_cam = Vec3::UnitZ();   ///< measured unit vector in the camera frame
  double residual = 0;          ///< [rad] angle between measured and fitted catalog direction
  bool operator==(const MatchedStar& o) const {
    return catalog_id == o.catalog_id && px == o.px && v_cam == o.v_cam && residual == o.residual;
  }
};

/// The body rate between two solved frames, measured by the tracker from the stars matched
/// in both (sensors/tracking/frame_rate.hpp; seed 004 ch. 7, eq. 7.1).
struct MeasuredRate {
  Vec3 rate_body = Vec3::Zero();    ///< [rad/s] mean body rate over the interval
  Mat3 cov_body = Mat3::Zero();     ///< [rad^2/s^2] from the two frames' star-vector noise
  double interval_s = 0;            ///< [s] the previous frame's time to this one's
  int stars = 0;                    ///< stars matched in both frames
  bool operator==(const MeasuredRate& o) const {
    return rate_body == o.rate_body && cov_body == o.cov_body && interval_s == o.interval_s &&
           stars == o.stars;
  }
};

/// Wall-clock time spent in each stage of the frame [s].
struct StageTimings {
  double detect = 0, identify = 0, attitude = 0, total = 0;
  bool operator==(const StageTimings& o) const {
    return detect == o.detect && identify == o.identify && attitude == o.attitude &&
           total == o.total;
  }
};

/// The outcome of one frame.
struct FrameResult {
  StarTrackerMode mode = StarTrackerMode::kFailed;
  FrameFailure failure = FrameFailure::kNone;  ///< kNone unless mode == kFailed
  std::string detail;         ///< human-readable detail of a failure or a note ("" when clean)
  PredictionSource prediction = PredictionSource::kNone;  ///< tracking frames
  bool fell_back_to_lost_in_space = false;  ///< this failure ended tracking (max_failed_frames)

  /// Body attitude, v_i = R(q_ib) v_b, and its body-frame covariance [rad^2]: only
  /// meaningful when hasAttitude().
  Quat q_ib = Quat::Identity();
  Mat3 cov_body = Mat3::Zero();
  std::vector<MatchedStar> stars;
  /// Body from camera of the stars' v_cam (the tracker's mounting, TrackerOptions::
  /// R_body_cam; identity for a joint fix of several heads, whose stars are body vectors).
  Mat3 R_body_cam = Mat3::Identity();
  int num_blobs = 0;          ///< blobs (or windows with a centroid) found in the image
  StageTimings timings;
  /// The camera model changed with this frame (healed by lost-in-space or refined online):
  /// StarTracker::camera() and cameraFit() tell how.
  bool camera_updated = false;
  double model_error_px = 0;  ///< [px] camera-model error term in force for this frame
  /// The body rate since the previous solved frame (when both share >= 2 stars and the
  /// previous frame is recent: TrackerOptions::max_propagation_s).
  std::optional<MeasuredRate> rate;

  bool hasAttitude() const { return mode != StarTrackerMode::kFailed; }
};

}  // namespace st
