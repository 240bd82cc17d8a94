// Shared helpers of the mrpt tests: sample observations with every field filled from a seed.
#pragma once
#include <mrpt/core/Clock.h>
#include <mrpt/obs/CObservationIMU.h>

#include <mrpt/serialization/CSerializable.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "common/attitude.hpp"
#include "common/errors.hpp"
#include "sensors/mrpt/observation_star_tracker.hpp"

namespace st::test {

using Bytes = std::vector<uint8_t>;

inline Bytes serialize(const mrpt::serialization::CSerializable& o) {
  Bytes b;
  mrpt::serialization::ObjectToOctetVector(&o, b);
  return b;
}

inline CObservationStarTracker::Ptr deserialize(const Bytes& b) {
  mrpt::serialization::CSerializable::Ptr p;
  mrpt::serialization::OctetVectorToObject(b, p);
  return std::dynamic_pointer_cast<CObservationStarTracker>(p);
}

/// Offset of the version byte in WriteObject's layout: [0x80 | len][class name][version][data].
inline std::size_t versionOffset() { return 1 + std::strlen("st::CObservationStarTracker"); }

/// A tracking fix with 8 stars, 42 blobs, non-trivial pose, covariance and timings; every
/// double drawn from `seed` so that no field is a round number.
inline CObservationStarTracker::Ptr makeStarTrackerObservation(uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto obs = CObservationStarTracker::Create();
  obs->timestamp = mrpt::Clock::fromDouble(1.7e9 + 0.1 * double(seed) + 1e-3 * u(rng));
  obs->sensorLabel = "STAR_TRACKER";
  obs->sensor_pose = mrpt::poses::CPose3D(0.1 * u(rng), 0.2 * u(rng), 0.3 * u(rng), u(rng),
                                          0.5 * u(rng), u(rng));
  obs->mode = StarTrackerMode::kTracking;
  obs->reason = "test fix";
  obs->q_ib = canonical(Quat(u(rng), u(rng), u(rng), u(rng)));
  Mat3 a;
  for (int i = 0; i < 9; ++i) a.data()[i] = 1e-5 * u(rng);
  obs->cov_body = a * a.transpose() + 1e-11 * Mat3::Identity();
  for (int k = 0; k < 8; ++k) {
    MatchedStar s;
    s.catalog_id = static_cast<uint32_t>(1000 + 977 * k + seed);
    s.px = Vec2(500 * (1 + u(rng)), 400 * (1 + u(rng)));
    s.v_cam = Vec3(0.1 * u(rng), 0.1 * u(rng), 1.0).normalized();
    s.residual = 1e-5 * (1 + u(rng));
    obs->stars.push_back(s);
  }
  obs->num_blobs = 42;
  obs->timings = {1e-3 * (1 + u(rng)), 2e-3 * (1 + u(rng)), 1e-4 * (1 + u(rng)), 5e-3};
  return obs;
}

inline mrpt::obs::CObservationIMU::Ptr makeGyroObservation(double t) {
  auto imu = mrpt::obs::CObservationIMU::Create();
  imu->sensorLabel = "GYRO";
  imu->timestamp = mrpt::Clock::fromDouble(1.7e9 + t);
  imu->set(mrpt::obs::IMU_WX, 0.01 * t);
  imu->set(mrpt::obs::IMU_WY, -0.02);
  imu->set(mrpt::obs::IMU_WZ, 0.003);
  return imu;
}

inline void writePlainFile(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream f(path, std::ios::binary);
  f.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

}  // namespace st::test
