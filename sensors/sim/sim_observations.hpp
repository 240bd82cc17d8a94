/// @file sim_observations.hpp
/// The simulator's data as stock MRPT observations, exactly as the rawlog contract says
/// (/work/briefs/contracts.md, "Rawlog format"), so any MRPT tool reads simulated rawlogs:
///  - CAMERA: CObservationImage, 8- or 16-bit grey, cameraParams = CameraModel::toTCamera(),
///    timestamp = mid-exposure;
///  - GYRO: CObservationIMU, IMU_WX/WY/WZ = mean body rate [rad/s] over the sample interval
///    ending at the timestamp (dataIsPresent set);
///  - GROUND_TRUTH: CObservation6DFeatures at each frame time: sensorPose = true q_ib (zero
///    translation), sensedFeatures[k]: id = catalog id, pose x, y = true pixel position at
///    mid-exposure, z = V magnitude.
#pragma once
#include <mrpt/core/Clock.h>
#include <mrpt/obs/CObservation6DFeatures.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationImage.h>

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "sensors/camera/camera_model.hpp"
#include "sensors/sim/star_renderer.hpp"

namespace st {

inline constexpr const char* kCameraLabel = "CAMERA";
inline constexpr const char* kGyroLabel = "GYRO";
inline constexpr const char* kGroundTruthLabel = "GROUND_TRUTH";

/// The image is deep-copied.
mrpt::obs::CObservationImage::Ptr makeCameraObservation(const cv::Mat& image,
                                                        const CameraModel& cam,
                                                        mrpt::Clock::time_point t,
                                                        const std::string& label = kCameraLabel);

mrpt::obs::CObservationIMU::Ptr makeGyroObservation(const Vec3& rate_body,
                                                    mrpt::Clock::time_point t,
                                                    const std::string& label = kGyroLabel);

mrpt::obs::CObservation6DFeatures::Ptr makeTruthObservation(
    const Quat& q_ib, const std::vector<TrueStar>& stars, mrpt::Clock::time_point t,
    const std::string& label = kGroundTruthLabel);

/// Reads a GROUND_TRUTH observation back (the inverse of makeTruthObservation; `electrons`
/// of the stars is not stored and comes back 0).
struct FrameTruth {
  Quat q_ib = Quat::Identity();
  std::vector<TrueStar> stars;
};
FrameTruth truthFromObservation(const mrpt::obs::CObservation6DFeatures& obs);

/// The body rate of a GYRO observation.
Vec3 rateFromObservation(const mrpt::obs::CObservationIMU& obs);

}  // namespace st
