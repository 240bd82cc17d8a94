/// @file frame_predictor.hpp
/// The tracker's own memory between frames, in the camera frame: the last fixes, from which
/// it predicts the next frame's attitude when no filter does, and the last measured rate,
/// from which it corrects a fix for the streak bias of an angular acceleration.
///
/// Prediction sources, first that applies:
///  - external: the caller's prediction (e.g. a filter's), used as given;
///  - gyro: the last fix propagated with the measured rate over the frame interval;
///  - rate match (seed 004 §5.5.3): the rate of the last two fixes, held constant.
/// With none of them (the frame after the first lost-in-space fix) there is no prediction.
/// Time: seconds on the caller's scale; only differences are used.
#pragma once
#include <optional>

#include "common/attitude.hpp"
#include "sensors/identify/recursive_id.hpp"
#include "sensors/tracking/frame.hpp"

namespace st {

struct FramePredictorOptions {
  bool frame_to_frame = true;     ///< propagate own fixes when nothing external is given
  double max_propagation_s = 1.0; ///< [s] older fixes are not propagated
  double accel_sigma = 0.05;      ///< [rad/s^2] 1-sigma angular acceleration (rate match)
  double gyro_sigma = 1e-4;       ///< [rad/s] 1-sigma error of a measured rate
  double exposure_s = 0.1;        ///< [s] for the acceleration correction
};

/// A solved frame, camera frame.
struct CameraFix {
  double t_s = 0;
  Quat q_ic = Quat::Identity();
  Mat3 cov_cam = Mat3::Zero();
};

class FramePredictor {
 public:
  explicit FramePredictor(FramePredictorOptions o) : opts_(o) {}

  /// The prediction for a frame at t_s and where it came from; `external` (camera frame) wins;
  /// `rate_cam` is the frame's measured rate (gyro, or the external prediction's).
  std::optional<CameraPrediction> predict(double t_s,
                                          const std::optional<CameraPrediction>& external,
                                          const std::optional<Vec3>& rate_cam,
                                          PredictionSource* source) const;

  /// Under an angular acceleration the stars' streak centroids are their exposure-mean
  /// positions, not their mid-exposure ones: corrects `fix` to mid-exposure, from this
  /// frame's rate and the last frame's. False when nothing was corrected.
  bool correctForAcceleration(const std::optional<Vec3>& rate_cam, CameraFix& fix) const;

  /// A tracking fix: the last one becomes the rate partner.
  void addTrackingFix(const CameraFix& fix);
  /// A lost-in-space fix: the last one stays the rate partner only when recent enough.
  void addLostInSpaceFix(const CameraFix& fix);
  /// The frame's measured rate (or none), for the next frame's acceleration.
  void recordRate(double t_s, const std::optional<Vec3>& rate_cam);
  void reset();

 private:
  FramePredictorOptions opts_;
  std::optional<CameraFix> last_, prev_;
  struct TimedRate {
    double t_s;
    Vec3 rate_cam;
  };
  std::optional<TimedRate> last_rate_;
};

}  // namespace st
