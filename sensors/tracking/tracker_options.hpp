/// @file tracker_options.hpp
/// Every tunable of the tracking stage (StarTracker), validated once at construction.
#pragma once
#include <string>

#include "common/attitude.hpp"
#include "sensors/detect/detector_options.hpp"
#include "sensors/identify/identifier.hpp"
#include "sensors/tracking/online_camera.hpp"

namespace st {

struct TrackerOptions {
  /// Camera mounting: body from camera, v_b = R_body_cam v_cam (identity: body = camera).
  Mat3 R_body_cam = Mat3::Identity();
  double exposure_s = 0.1;  ///< [s] for the blur of predicted stars

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

  // --- the camera model (issue 19) ---
  /// Lost-in-space heals a camera file that fails as it is: focal lengths within +-this
  /// (relative) are searched and refined with the distortion (0: the file is taken as exact).
  double camera_heal_range = 0.05;
  /// Online refinement from verified frames and the camera-model error term.
  OnlineCameraOptions online_camera;

  // --- tracking ---
  std::string solver = WahbaSolver::defaultName();   ///< Wahba solver while tracking
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
  /// Nor those whose centroid a star fainter than the database (its blend screen) would pull
  /// by more than this many centroid sigmas: f / (1 + f) x separation, f the flux ratio.
  double screen_pull_sigma = 1.0;
  double loss_probability = 1e-3;     ///< false-alarm rate of the chi-square loss test
  double consistency_probability = 1e-3;  ///< of the prediction-consistency test
  int max_failed_frames = 3;      ///< consecutive failed tracking frames -> lost-in-space
  /// A frame whose windows find too few stars (too-few-in-gate, too-few-predicted) is solved
  /// lost-in-space at once, in the same frame, whatever predicted it: consecutive frames can
  /// be unrelated (minutes apart, after a tumble, a slideshow through a folder), and waiting
  /// for max_failed_frames loses them. Without it only a prediction from our own last fixes
  /// (the rate match) does so.
  bool reacquire_in_frame = true;
  /// [s] the time that lost-in-space may take in such a frame (0 = no limit): the next frame
  /// must not wait behind a search in a sky it cannot solve.
  double reacquire_budget_s = 0.5;

  // --- frame-to-frame prediction ---
  bool frame_to_frame = true;     ///< propagate our own attitudes when nothing is given
  double max_propagation_s = 1.0; ///< [s] older attitudes are not propagated
  double accel_sigma = 0.05;      ///< [rad/s^2] 1-sigma angular acceleration (rate-match model)
  double gyro_sigma = 1e-4;       ///< [rad/s] 1-sigma error of FrameInputs::rate_body

  /// False, with "option 'name': why" in *why, when a value is unusable (names of algorithms
  /// and solvers included).
  bool isValid(std::string* why = nullptr) const;
  /// The edge's wrapper: throws InputError("star tracker option 'name': why").
  void validate() const;
};

}  // namespace st
