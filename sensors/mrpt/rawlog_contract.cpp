#include "sensors/mrpt/rawlog_contract.hpp"

#include <mrpt/img/CImage.h>
#include <mrpt/poses/CPose3D.h>

#include "common/check.hpp"
#include "common/mrpt_convert.hpp"
#include "sensors/mrpt/camera_ini.hpp"

namespace st {

mrpt::obs::CObservationImage::Ptr makeCameraObservation(const cv::Mat& image,
                                                        const CameraModel& cam,
                                                        mrpt::Clock::time_point t,
                                                        const std::string& label,
                                                        const mrpt::poses::CPose3D& mount) {
  auto obs = mrpt::obs::CObservationImage::Create();
  obs->timestamp = t;
  obs->sensorLabel = label;
  obs->cameraPose = mount;
  obs->cameraParams = toTCamera(cam);
  obs->image = mrpt::img::CImage(image, mrpt::img::DEEP_COPY);
  return obs;
}

mrpt::obs::CObservationIMU::Ptr makeGyroObservation(const Vec3& rate_body,
                                                    mrpt::Clock::time_point t,
                                                    const std::string& label) {
  auto obs = mrpt::obs::CObservationIMU::Create();
  obs->timestamp = t;
  obs->sensorLabel = label;
  obs->set(mrpt::obs::IMU_WX, rate_body.x());
  obs->set(mrpt::obs::IMU_WY, rate_body.y());
  obs->set(mrpt::obs::IMU_WZ, rate_body.z());
  return obs;
}

mrpt::obs::CObservationIMU::Ptr makeVelocityObservation(const Vec3& velocity_km_s,
                                                        mrpt::Clock::time_point t,
                                                        const std::string& label) {
  auto obs = mrpt::obs::CObservationIMU::Create();
  obs->timestamp = t;
  obs->sensorLabel = label;
  obs->set(mrpt::obs::IMU_X_VEL, 1e3 * velocity_km_s.x());
  obs->set(mrpt::obs::IMU_Y_VEL, 1e3 * velocity_km_s.y());
  obs->set(mrpt::obs::IMU_Z_VEL, 1e3 * velocity_km_s.z());
  return obs;
}

mrpt::obs::CObservation6DFeatures::Ptr makeTruthObservation(const FrameTruth& truth,
                                                            mrpt::Clock::time_point t,
                                                            const std::string& label) {
  auto obs = mrpt::obs::CObservation6DFeatures::Create();
  obs->timestamp = t;
  obs->sensorLabel = label;
  obs->sensorPose = mrpt::poses::CPose3D(toPose3DQuat(truth.q_ib));
  for (const TruthStar& s : truth.stars) {
    mrpt::obs::CObservation6DFeatures::TMeasurement m;
    ST_ASSERT(s.id < (1u << 24) && s.head >= 0 && s.head < kMaxTruthHeads);
    m.id = static_cast<int32_t>(s.id | (static_cast<uint32_t>(s.head) << 24));
    m.pose = mrpt::poses::CPose3D(s.px.x(), s.px.y(), s.mag, 0, 0, 0);
    obs->sensedFeatures.push_back(m);
  }
  return obs;
}

FrameTruth truthFromObservation(const mrpt::obs::CObservation6DFeatures& obs) {
  FrameTruth out;
  out.q_ib = fromPose3DQuat(mrpt::poses::CPose3DQuat(obs.sensorPose));
  for (const auto& m : obs.sensedFeatures)
    out.stars.push_back({static_cast<uint32_t>(m.id) & 0xFFFFFFu, Vec2(m.pose.x(), m.pose.y()),
                         m.pose.z(), static_cast<int>((static_cast<uint32_t>(m.id) >> 24) & 0x3F)});
  return out;
}

Vec3 rateFromObservation(const mrpt::obs::CObservationIMU& obs) {
  return Vec3(obs.get(mrpt::obs::IMU_WX), obs.get(mrpt::obs::IMU_WY), obs.get(mrpt::obs::IMU_WZ));
}

std::optional<Vec3> velocityFromObservation(const mrpt::obs::CObservationIMU& obs) {
  using namespace mrpt::obs;
  if (!obs.has(IMU_X_VEL) || !obs.has(IMU_Y_VEL) || !obs.has(IMU_Z_VEL)) return std::nullopt;
  return Vec3(obs.get(IMU_X_VEL), obs.get(IMU_Y_VEL), obs.get(IMU_Z_VEL)) * 1e-3;
}

}  // namespace st
