/// @file rawlog_contract.hpp
/// The rawlog contract (DESIGN.md "Rawlogs"): which stock MRPT observation carries what, under
/// which label, so that any MRPT tool reads our rawlogs and any producer (the simulator, a
/// real camera + IMU, a recording of `live`) can feed `replay`:
///  - CAMERA: CObservationImage, 8- or 16-bit grey, cameraParams = toTCamera(camera),
///    timestamp = mid-exposure;
///  - GYRO: CObservationIMU, IMU_WX/WY/WZ = mean body rate [rad/s] over the sample interval
///    ending at the timestamp (dataIsPresent set);
///  - GROUND_TRUTH (simulated runs only): CObservation6DFeatures at each frame time:
///    sensorPose = true q_ib (zero translation), sensedFeatures[k]: id = catalog id,
///    pose x, y = true pixel position at mid-exposure, z = V magnitude;
///  - VELOCITY (optional): CObservationIMU, IMU_X_VEL/Y_VEL/Z_VEL = the observer's velocity
///    [m/s] in the inertial frame, relative to the Earth's centre (the part of its motion whose
///    aberration the star database does not hold: the database is aberrated for the Earth's
///    orbit at its epoch), e.g. an orbit's velocity from the on-board propagator;
///  - STAR_TRACKER: CObservationStarTracker (observation_star_tracker.hpp).
/// The encoders and decoders live here, once; the simulator and the navigator both use them.
#pragma once
#include <mrpt/core/Clock.h>
#include <mrpt/obs/CObservation6DFeatures.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationImage.h>

#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/attitude.hpp"
#include "sensors/camera/camera_model.hpp"

namespace st {

inline constexpr const char* kCameraLabel = "CAMERA";
inline constexpr const char* kGyroLabel = "GYRO";
inline constexpr const char* kGroundTruthLabel = "GROUND_TRUTH";
inline constexpr const char* kStarTrackerLabel = "STAR_TRACKER";
inline constexpr const char* kVelocityLabel = "VELOCITY";

/// One true star of a GROUND_TRUTH observation.
struct TruthStar {
  uint32_t id = 0;         ///< catalog id
  Vec2 px = Vec2::Zero();  ///< [px] true image position at mid-exposure, in its head's image
  double mag = 0;          ///< V magnitude
  /// The camera head whose image holds it (0: the first; a scenario's head_sections order).
  /// Encoded in the feature id's bits 24-29 (catalog ids are < 2^24), so that a one-head
  /// rawlog's truth is what it always was.
  int head = 0;
};
inline constexpr int kMaxTruthHeads = 64;

/// A GROUND_TRUTH observation decoded.
struct FrameTruth {
  Quat q_ib = Quat::Identity();
  std::vector<TruthStar> stars;
};

/// The image is deep-copied. `mount` (the head's pose on the body, MRPT's cameraPose) is the
/// mounting a replay gives that head's tracker: body from camera.
mrpt::obs::CObservationImage::Ptr makeCameraObservation(
    const cv::Mat& image, const CameraModel& cam, mrpt::Clock::time_point t,
    const std::string& label = kCameraLabel,
    const mrpt::poses::CPose3D& mount = mrpt::poses::CPose3D());
mrpt::obs::CObservationIMU::Ptr makeGyroObservation(const Vec3& rate_body,
                                                    mrpt::Clock::time_point t,
                                                    const std::string& label = kGyroLabel);
/// `velocity_km_s` in the contract's m/s.
mrpt::obs::CObservationIMU::Ptr makeVelocityObservation(const Vec3& velocity_km_s,
                                                        mrpt::Clock::time_point t,
                                                        const std::string& label = kVelocityLabel);
mrpt::obs::CObservation6DFeatures::Ptr makeTruthObservation(
    const FrameTruth& truth, mrpt::Clock::time_point t,
    const std::string& label = kGroundTruthLabel);

FrameTruth truthFromObservation(const mrpt::obs::CObservation6DFeatures& obs);
/// The body rate of a GYRO observation.
Vec3 rateFromObservation(const mrpt::obs::CObservationIMU& obs);
/// The velocity [km/s] of a VELOCITY observation; nothing when it lacks one of the three
/// components.
std::optional<Vec3> velocityFromObservation(const mrpt::obs::CObservationIMU& obs);

}  // namespace st
