/// @file observation_star_tracker.hpp
/// `st::CObservationStarTracker`: one star-tracker fix as an MRPT observation, so that it can
/// be stored in rawlogs (label `STAR_TRACKER`), shown in RawLogViewer and read by the stock
/// tools through the plugin (sensors/mrpt/plugin/).
///
/// Registration is manual (MRPT-NOTES.md): call st::registerStarTrackerClasses() (rawlog_io.hpp)
/// before reading a rawlog, or MRPT's CRawlog silently stops at the first such object.
///
/// Serialization versions (serializeGetVersion returns kCurrentVersion unless a writer asks
/// for an older layout with setWriteVersion):
///   0: timestamp, label, sensor pose, mode, reason, q_ib, covariance, stars, blobs
///   1: + per-stage timings (version-0 objects read with timings = 0)
///   2: + failure (FrameFailure, uint8); older objects read with failure = kNone for a fix
///      and kUnknown for a failed frame (their kind was not recorded)
///   3: + the body rate since the previous fix (uint8 present; then rate [rad/s] x3, its
///      covariance [rad^2/s^2] 3x3 column-major, interval [s], stars int32); older objects
///      read with no rate
///
/// Mode, failure, MatchedStar and StageTimings are the tracking stage's
/// (sensors/tracking/frame.hpp); observation_from_frame.hpp converts a FrameResult.
#pragma once
#include <mrpt/obs/CObservation.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CSerializable.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "startracker/attitude.hpp"
#include "startracker/frame.hpp"

namespace st {

class CObservationStarTracker : public mrpt::obs::CObservation {
  DEFINE_SERIALIZABLE(CObservationStarTracker, st)

 public:
  static constexpr uint8_t kCurrentVersion = 3;

  CObservationStarTracker() = default;

  StarTrackerMode mode = StarTrackerMode::kFailed;
  FrameFailure failure = FrameFailure::kNone;  ///< kNone unless mode == kFailed
  std::string reason;  ///< why it failed, or notes ("" when all went well)

  /// Attitude of the body in the inertial frame, v_i = R(q_ib) v_b (conventions.hpp). Only
  /// meaningful when hasAttitude().
  Quat q_ib = Quat::Identity();
  /// 3x3 covariance of the body-frame rotation error [rad^2].
  Mat3 cov_body = Mat3::Zero();

  std::vector<MatchedStar> stars;
  int32_t num_blobs = 0;  ///< blobs (or windows with a centroid) found in the image
  StageTimings timings;
  /// The body rate measured from this frame and the tracker's previous fix (frame.hpp):
  /// body frame; absent for the first fix or frames without common stars.
  std::optional<MeasuredRate> rate;

  /// Pose of the camera on the vehicle (body frame); identity by default.
  mrpt::poses::CPose3D sensor_pose;

  bool hasAttitude() const { return mode != StarTrackerMode::kFailed; }

  void getSensorPose(mrpt::poses::CPose3D& out_sensorPose) const override {
    out_sensorPose = sensor_pose;
  }
  void setSensorPose(const mrpt::poses::CPose3D& p) override { sensor_pose = p; }
  using CObservation::getSensorPose;
  using CObservation::setSensorPose;

  /// Shown by RawLogViewer and `rawlog-edit --info`-style tools.
  void getDescriptionAsText(std::ostream& o) const override;

  /// Layout written by serializeTo (default kCurrentVersion). Older numbers exist so files for
  /// older readers can be produced and so the old-version load path stays tested.
  void setWriteVersion(uint8_t v);
  uint8_t writeVersion() const { return write_version_; }

  /// All fields equal (exact comparison; timestamps compared as ticks).
  bool sameContent(const CObservationStarTracker& o) const;

 private:
  uint8_t write_version_ = kCurrentVersion;
};

}  // namespace st
