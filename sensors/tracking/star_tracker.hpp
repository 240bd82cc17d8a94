/// @file star_tracker.hpp
/// The tracking stage: one image (+ its mid-exposure time and what the outside knows,
/// FrameInputs) in, one FrameResult out. It keeps its own state between frames. MRPT-free;
/// sensors/mrpt/ turns its results into CObservationStarTracker.
///
/// Modes (seed 003: initial-estimate vs predictional-estimate; seed 002: recursive star-ID)
///  - lost-in-space: full-frame detection (detectStars, streaks re-measured:
///    detect/streaks.hpp) + a lost-in-space identifier (sensors/identify, default "pyramid").
///    Used when there is no usable prediction.
///  - tracking: a prediction (FrameInputs::prediction, e.g. a filter's, or the tracker's own
///    frame-to-frame one, frame_predictor.hpp) drives recursive identification
///    (identify/recursive_id.hpp: predicted windows + Mahalanobis gate); a Wahba solve
///    ("quest" by default) over the gated stars, refined in pixel space with each centroid's
///    full covariance (attitude/pixel_refinement.hpp); verification: the residual chi-square
///    (~ chi2(2n-3), the worst star dropped while it fails, attitude/drop_worst.hpp), at least
///    min_tracked_stars stars, and the solution consistent with the prediction (chi2(3) on
///    Log(q_pred^-1 q_sol) with P_pred + P_sol).
///    After max_failed_frames consecutive failed tracking frames the tracker drops back to
///    lost-in-space by itself (and ignores predictions until lost-in-space succeeds again, so
///    a diverged filter cannot keep it failing).
///  - rate: every fix whose stars share >= 2 catalog ids with the last solved frame (no
///    older than max_propagation_s) carries the body rate between the two (FrameResult::rate,
///    frame_rate.hpp: relative attitude of the two frames, seed 004 eq. 7.1).
///  - re-acquisition: a prediction whose windows find too few stars (the scene changed: an
///    unrelated frame, a jump) is not retried on the next frames: the same frame goes to
///    lost-in-space at once, within reacquire_budget_s (TrackerOptions::reacquire_in_frame;
///    off, only a frame-to-frame prediction does so and a filter's or a gyro's waits for
///    max_failed_frames). Other failures (the solve, the prediction-consistency test) count
///    towards max_failed_frames.
///
/// The camera (issue 19): the camera file is a starting point, not the truth. Lost-in-space
/// identifies with it as it is and, when that fails before any fix has verified the camera,
/// heals it (focal length searched and
/// refined within +-camera_heal_range, distortion fitted: identify/camera_refine.hpp); the
/// verified frames refine it online (online_camera.hpp: focal length, principal point, k1,
/// the file as the first prior), and the residuals give a camera-model error term [px] added
/// to every centroid's sigma in the gates and the fixes' covariances. camera() is the model
/// in force; the sensor records it with every frame.
///
/// Observer velocity (FrameInputs::observer_velocity_km_s, observer_aberration.hpp): the fix is
/// against the stars' apparent directions for that observer. Windows and gates use the
/// database's directions (5" is a twentieth of a pixel of a 15 deg lens next to gates of
/// several pixels).
///
/// Frames: identification, windows and fixes work in the camera frame (q_ic, cov_cam);
/// FrameInputs and FrameResult are in the body frame of TrackerOptions::R_body_cam.
/// Time: seconds on the caller's monotonic scale; only differences are used.
///
/// Not thread-safe; one tracker per camera. The database must outlive it.
#pragma once
#include <memory>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "catalog/star_database.hpp"
#include "common/chi_square.hpp"
#include "sensors/attitude/pixel_refinement.hpp"
#include "sensors/attitude/wahba.hpp"
#include "sensors/camera/camera_model.hpp"
#include "sensors/identify/identifier.hpp"
#include "sensors/detect/star_detector.hpp"
#include "sensors/identify/recursive_id.hpp"
#include "sensors/tracking/frame.hpp"
#include "sensors/tracking/frame_predictor.hpp"
#include "sensors/tracking/frame_rate.hpp"
#include "sensors/tracking/online_camera.hpp"
#include "sensors/tracking/tracker_options.hpp"

namespace st {

/// The note a frame's detail carries when its windows found too few stars and it was solved
/// lost-in-space in the same frame (TrackerOptions::reacquire_in_frame): summaries count
/// such re-acquisitions by it (reacquiredInFrame).
constexpr const char* kReacquiredNote = "lost-in-space in the same frame";
/// True for a frame solved by such a re-acquisition (its mode and recorded detail).
inline bool reacquiredInFrame(StarTrackerMode mode, const std::string& detail) {
  return mode == StarTrackerMode::kLostInSpace && detail.find(kReacquiredNote) != std::string::npos;
}

class StarTracker {
 public:
  /// Throws InputError naming the option when `options` is unusable (TrackerOptions::isValid).
  StarTracker(const StarDatabase& db, const CameraModel& camera, TrackerOptions options = {});
  ~StarTracker();
  StarTracker(const StarTracker&) = delete;
  StarTracker& operator=(const StarTracker&) = delete;

  /// Processes one 8- or 16-bit grey frame whose mid-exposure time is t_s [s].
  FrameResult process(const cv::Mat& image, double t_s, const FrameInputs& in = {});

  /// Forgets everything: the next frame runs lost-in-space.
  void reset();

  bool isLost() const { return lost_; }
  int consecutiveFailures() const { return failed_frames_; }
  const TrackerOptions& options() const { return opts_; }
  /// The camera model in force (the file's, healed or refined online).
  const CameraModel& camera() const { return camera_; }
  /// [px] the camera-model error term in force (0 until residuals show one).
  double modelErrorPx() const { return model_error_px_; }
  /// The last online or healing fit of the camera, with its uncertainties.
  const std::optional<CameraFitResult>& cameraFit() const { return online_.lastFit(); }

 private:
  struct Failure {
    FrameFailure kind;
    std::string detail;
  };
  bool track(const cv::Mat& image, const CameraPrediction& pred, PredictionSource source,
             FrameResult& out, CameraFix& fix);
  /// The Wahba solve + pixel refinement over the gated stars, the worst dropped while the
  /// residual test fails; nullopt on success.
  std::optional<Failure> solveTracked(const CameraPrediction& pred, FrameResult& out,
                                      CameraFix& fix);
  /// `budget_s` > 0: the search stops after that long (SearchLimits::deadline).
  bool lostInSpace(const cv::Mat& image, const std::optional<Vec3>& rate_cam, FrameResult& out,
                   CameraFix& fix, double budget_s = 0);
  /// Re-measures full-frame streaks (detect/streaks.hpp) from the measured rate, else from
  /// the blobs' shapes; returns the camera-frame rate that draws them (the measured one, or
  /// the cross-boresight rate of the shapes' streak), nothing for round stars.
  std::optional<Vec3> measureStreaksOf(const cv::Mat& image, const std::optional<Vec3>& rate_cam,
                                       std::vector<Centroid>& stars);
  Vec2 imageCentre() const;
  /// [px] 1-sigma at the image centre, along its worst direction, of a camera-frame
  /// covariance (of an attitude [rad^2], or of a rate times the exposure).
  double sigmaAtCentrePx(const Mat3& cov_cam) const;
  /// [px] the streak length at the image centre for a camera-frame rate.
  double streakPx(const Vec3& rate_cam) const;
  /// A streaked lost-in-space fix measured again as tracking measures a frame, predicted by
  /// itself; false (the fix kept) when tracking cannot confirm it.
  bool remeasureAsTracking(const cv::Mat& image, const Vec3& rate_cam, FrameResult& out,
                           CameraFix& fix);
  void setAttitude(FrameResult& out, const CameraFix& fix) const;
  /// A database star's direction as this frame's observer sees it (FrameInputs::
  /// observer_velocity_km_s; the database's own without one).
  Vec3 referenceDirection(uint32_t star_index) const;
  /// A lost-in-space fix becomes the frame's answer and the predictor's new start.
  void acceptLostInSpace(const std::optional<Vec3>& rate_cam, CameraFix& fix, FrameResult& out);
  /// A verified frame's stars into the online camera fit; adopts its result.
  void learnCamera(const Quat& q_ic, FrameStars stars, FrameResult& out);
  void useCamera(const CameraModel& camera, double model_error_px);

  const StarDatabase& db_;
  CameraModel camera_;
  TrackerOptions opts_;
  StarDetector detector_;  // full-frame detection and streak re-measurement
  DetectionResult det_;    // its result, capacity kept between frames
  Mat3 R_bc_ = Mat3::Identity();  // body from camera
  std::unique_ptr<StarIdentifier> identifier_;
  std::unique_ptr<WahbaSolver> solver_;
  RecursiveIdentifier recursive_;
  FramePredictor predictor_;
  ChiSquareThresholds loss_threshold_;  // by dof = 2n - 3, n <= max_tracked_stars
  double consistency_threshold_ = 0;    // chi2(3)
  int failed_frames_ = 0;
  bool lost_ = true;
  OnlineCamera online_;
  double model_error_px_ = 0;
  bool camera_verified_ = false;  // a fix verified with camera_: no more healing searches
  // The last solved frame's stars: the partner of the next fix's rate (frame_rate.hpp). Kept
  // through reset(): its identities were verified, whatever the mode of the next fix.
  std::optional<RateFrame> rate_prev_;
  std::optional<Vec3> velocity_;  // this frame's observer velocity [km/s] (aberration)

  // Scratch buffers kept between frames.
  RecursiveIdResult rid_;
  std::vector<StarObservation> sobs_;
  std::vector<VectorObservation> vobs_;
  std::vector<PixelObservation> pix_;
  std::vector<std::size_t> keep_;
  std::vector<double> e2_;
};

}  // namespace st
