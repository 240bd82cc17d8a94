/// @file star_tracker_pipeline.hpp
/// The star tracker as a frame-by-frame process: one image (+ its mid-exposure timestamp) in,
/// one CObservationStarTracker out. It keeps its own state between frames.
///
/// Modes (seed 003: initial-estimate vs predictional-estimate; seed 002: recursive star-ID)
///  - lost-in-space: full-frame detection (detectStars) + a lost-in-space identifier
///    (sensors/identify, default "pyramid"). Used when there is no usable prediction.
///  - tracking: a prediction (attitude, body-frame covariance, body rate at the frame time)
///    comes either from outside (setPrediction, e.g. the filter's) or from the pipeline itself
///    (frame-to-frame mode, see below). Then
///      1. cone query of the catalog around the predicted boresight, projection into the
///         camera (pinhole + distortion); stars entering the FOV are picked up by the same
///         projection, no separate search is needed;
///      2. a window per predicted star, sized from the attitude covariance projected into
///         pixels (H P H^T, H = d(pixel)/d(dtheta)) and the blur (rate x exposure) (seed 004
///         §4.2.3 predictive centroiding); `centroidWindows` reads only those pixels;
///      3. Mahalanobis gate per star: d^T (H P H^T + C_centroid)^-1 d <= gate_sigma^2. With
///         both covariances sigma^2 I this is |d| <= 3 sqrt(2) sigma (seed 002 step 5) for the
///         default gate_sigma = 3;
///      4. Wahba solve ("quest" by default) over the gated stars;
///      5. refinement with each centroid's full 2x2 covariance (Gauss-Newton on the pixel
///         residuals from the Wahba solution; covariance = inverse Fisher information);
///         verification: chi-square test of the residuals (~ chi2(2n-3), the worst
///         star removed while it fails), at least min_tracked_stars stars, and the solved
///         attitude consistent with the prediction (chi2(3) on Log(q_pred^-1 q_sol) with
///         P_pred + P_sol).
///    After max_failed_frames consecutive failed tracking frames the pipeline drops back to
///    lost-in-space by itself (and ignores predictions until lost-in-space succeeds again, so
///    a diverged filter cannot keep it failing).
///  - frame-to-frame (no filter): the previous attitude propagated to the frame time with
///      a gyro rate given by setGyroRate(), or else the rate of the last two attitudes (the
///      rate match of seed 004 §5.5.3: constant rate between frames). With neither (the frame
///      after the first lost-in-space fix) the frame runs lost-in-space again.
///
/// Frames: the identification and the windows work in the camera frame; q_ib, the covariance
/// and the body rate in the observation and in predictions are in the body frame given by
/// `sensor_pose` (identity: body = camera), conventions.hpp.
///
/// Not thread-safe; one pipeline per camera. The database and camera must outlive it.
#pragma once
#include <mrpt/core/Clock.h>
#include <mrpt/poses/CPose3D.h>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "catalog/star_database.hpp"
#include "common/attitude.hpp"
#include "sensors/attitude/wahba.hpp"
#include "sensors/camera/camera_model.hpp"
#include "sensors/detect/detector_options.hpp"
#include "sensors/identify/identifier.hpp"
#include "sensors/mrpt/observation_star_tracker.hpp"

namespace mrpt::config {
class CConfigFileBase;
}

namespace st {

struct PipelineOptions {
  std::string sensor_label = "STAR_TRACKER";
  mrpt::poses::CPose3D sensor_pose;  ///< camera on the vehicle (v_b = R v_cam); identity
  double exposure_s = 0.1;            ///< [s] for the blur of predicted stars

  // --- lost-in-space ---
  std::string lis_algorithm = "pyramid";  ///< sensors/identify registry name
  IdentifyOptions identify;               ///< identify.solver is the Wahba solver of LIS
  DetectorOptions detect;                 ///< full-frame and window detection
  /// [px] floor of a centroid's sigma for lost-in-space (toStarObservations): the
  /// identification's gates and its fix covariance. Pessimistic for bright stars (their
  /// centroid sigma is ~0.004-0.01 px) but it only matters for the first frame.
  double min_sigma_px = 0.02;
  /// [px] floor of a centroid's sigma while tracking: only a guard against a zero
  /// covariance, so below the Cramer-Rao bound of the best centroid, sigma_psf /
  /// sqrt(electrons) = 1 / sqrt(1.4e5) = 0.0027 px for the brightest unsaturated star of a
  /// 20,000 e- full well (14.7 % of a sigma = 1 px PSF in the peak pixel). A floor above the
  /// bound (0.02 px before) makes the tracking fixes of bright stars ~3x pessimistic.
  double tracking_min_sigma_px = 0.001;

  // --- tracking ---
  std::string solver = "quest";   ///< Wahba solver while tracking
  int max_tracked_stars = 20;     ///< windows per frame (brightest predicted stars)
  int min_tracked_stars = 4;      ///< fewer gated stars -> failed frame
  /// Leave saturated stars out of the tracking fix while at least min_tracked_stars others
  /// remain: the fit rests on their wings, and their errors exceed the covariance it reports
  /// (one-hour run, 8-bit frames with Sirius in view: raw fixes' NEES 93.9 % below the chi2(3)
  /// 95 % point with them, 95.5 % without, for 4 % more error).
  bool drop_saturated = true;
  double gate_sigma = 3.0;        ///< Mahalanobis gate (3 -> 3 sqrt(2) sigma, seed 002)
  double edge_margin_px = 4.0;    ///< predicted stars closer to the border are not windowed
  /// Predicted stars closer than this to another catalog star are not windowed: their
  /// images blend and the centroid would be biased or taken by the wrong star.
  double blend_separation_px = 5.0;
  double loss_probability = 1e-3;     ///< false-alarm rate of the chi-square loss test
  double consistency_probability = 1e-3;  ///< of the prediction-consistency test
  int max_failed_frames = 3;      ///< consecutive failed tracking frames -> lost-in-space

  // --- frame-to-frame prediction ---
  bool frame_to_frame = true;     ///< propagate our own attitudes when nothing is given
  double max_propagation_s = 1.0; ///< [s] older attitudes are not propagated
  double accel_sigma = 0.05;      ///< [rad/s^2] 1-sigma angular acceleration (rate-match model)
  double gyro_sigma = 1e-4;       ///< [rad/s] 1-sigma error of a rate given by setGyroRate

  /// Throws InputError naming the option when a value is unusable.
  void validate() const;
};

class StarTrackerPipeline {
 public:
  /// Throws InputError for bad options (unknown algorithm or solver name, ...).
  StarTrackerPipeline(const StarDatabase& db, const CameraModel& camera,
                      PipelineOptions options = {});
  ~StarTrackerPipeline();
  StarTrackerPipeline(const StarTrackerPipeline&) = delete;
  StarTrackerPipeline& operator=(const StarTrackerPipeline&) = delete;

  /// Processes one 8- or 16-bit grey frame whose mid-exposure time is `t`.
  CObservationStarTracker::Ptr process(const cv::Mat& image, mrpt::Clock::time_point t);

  /// Prediction for the next processed frame only (e.g. the filter's). Ignored while lost.
  void setPrediction(const AttitudePrediction& prediction);
  /// Body rate [rad/s] over the interval up to the next frame (frame-to-frame mode with a
  /// gyro), for the next processed frame only.
  void setGyroRate(const Vec3& rate_body);

  /// Forgets everything: the next frame runs lost-in-space.
  void reset();

  bool isLost() const { return lost_; }
  int consecutiveFailures() const { return failed_frames_; }
  const PipelineOptions& options() const { return opts_; }

 private:
  struct Fix {  // a solved frame, camera frame
    mrpt::Clock::time_point t;
    Quat q_ic;
    Mat3 cov_cam;
  };
  struct Prediction {  // camera frame
    Quat q_ic;
    Mat3 cov_cam;
    Vec3 rate_cam;
    std::string source;
  };

  /// `rate_cam`: the measured rate (camera frame) of this frame's prediction or gyro input.
  std::optional<Prediction> predictionFor(mrpt::Clock::time_point t,
                                          const std::optional<Vec3>& rate_cam);
  bool track(const cv::Mat& image, const Prediction& pred, CObservationStarTracker& out,
             Fix& fix);
  /// `rate_cam`: the body rate (camera frame) when a gyro gave one, to measure streaks whole.
  bool lostInSpace(const cv::Mat& image, const std::optional<Vec3>& rate_cam,
                   CObservationStarTracker& out, Fix& fix);
  /// Full-frame centroids of streaks re-measured over the whole streak `blur_at` gives at
  /// each star (fragments of a faint streak merged); round stars untouched.
  void measureStreaks(const cv::Mat& image, const std::function<Vec2(const Vec2&)>& blur_at,
                      std::vector<Centroid>& stars) const;
  void setAttitude(CObservationStarTracker& out, const Quat& q_ic, const Mat3& cov_cam) const;
  /// Under an angular acceleration the stars' streak centroids are their exposure-mean
  /// positions, not their mid-exposure ones: corrects the fix to mid-exposure.
  void correctForAcceleration(const std::optional<Vec3>& rate_cam, mrpt::Clock::time_point t,
                              CObservationStarTracker& out, Fix& fix);

  const StarDatabase& db_;
  CameraModel camera_;
  PipelineOptions opts_;
  Mat3 R_bc_ = Mat3::Identity();  // body from camera
  double half_diagonal_fov_ = 0;  // [rad] cached: the cone that holds the image
  std::unique_ptr<StarIdentifier> identifier_;
  std::unique_ptr<WahbaSolver> solver_;

  std::optional<Fix> last_, prev_;
  std::optional<AttitudePrediction> external_;
  std::optional<Vec3> gyro_rate_body_;
  /// The last frame's body rate (camera frame) from a gyro or a prediction: with this
  /// frame's it gives the angular acceleration, whose streak bias the fix is corrected for.
  struct TimedRate {
    mrpt::Clock::time_point t;
    Vec3 rate_cam;
  };
  std::optional<TimedRate> last_rate_;
  int failed_frames_ = 0;
  bool lost_ = true;

  // Scratch buffers kept between frames (no allocation while tracking).
  std::vector<uint32_t> cone_;
  struct Candidate;
  std::vector<Candidate> candidates_;
};

}  // namespace st
