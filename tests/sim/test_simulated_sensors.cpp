// The simulated camera and gyro as MRPT sensors: factory registration, .ini configuration,
// real-time emission on one clock, and the same data as the offline simulator.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <chrono>
#include <fstream>
#include <thread>

#include "sensors/sim/scenario.hpp"
#include "sensors/sim/sim_observations.hpp"
#include "sensors/sim/simulated_sensors.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

std::string writeScenario() {
  const std::string path = test::makeTempDir("simsensor") + "/live.ini";
  std::ofstream(path) << R"(
[scenario]
duration_s = 0.5
frame_rate_hz = 20
start_time = 2025-03-20T00:00:00
seed = 3
[camera]
resolution = [128 96]
fov_deg = 10
[sensor]
exposure_s = 0.02
gain_e_per_adu = 4
[motion]
type = slew
ra_deg = 84
dec_deg = -2
rate_deg_s = 0 1 0
[gyro]
rate_hz = 100
arw_deg_rt_h = 0.1
rrw_deg_h_rt_h = 0.5
bias_deg_h = 1
)";
  return path;
}

TEST(SimulatedSensors, RegisteredAndRunInRealTimeOnOneClock) {
  EXPECT_EQ(mrpt::hwdrivers::CGenericSensor::createSensorPtr("CSimulatedGyro"), nullptr);
  registerSimulatedSensors();
  auto cam_base = mrpt::hwdrivers::CGenericSensor::createSensorPtr("CSimulatedStarCamera");
  auto gyro_base = mrpt::hwdrivers::CGenericSensor::createSensorPtr("CSimulatedGyro");
  ASSERT_NE(cam_base, nullptr);
  ASSERT_NE(gyro_base, nullptr);
  const std::string scenario = writeScenario();
  mrpt::config::CConfigFileMemory cfg(
      "[CAM]\ndriver = CSimulatedStarCamera\nprocess_rate = 200\nsensorLabel = CAMERA\n"
      "scenario_file = " + scenario + "\n"
      "[GYRO]\ndriver = CSimulatedGyro\nprocess_rate = 200\nsensorLabel = GYRO\n"
      "scenario_file = " + scenario + "\n");
  cam_base->loadConfig(cfg, "CAM");
  gyro_base->loadConfig(cfg, "GYRO");
  cam_base->initialize();
  gyro_base->initialize();
  resetSimulatedSensorsClock();
  auto* cam = dynamic_cast<CSimulatedStarCamera*>(cam_base.get());
  auto* gyro = dynamic_cast<CSimulatedGyro*>(gyro_base.get());
  ASSERT_TRUE(cam && gyro);

  mrpt::hwdrivers::CGenericSensor::TListObservations all;
  const auto t_end = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!(cam->finished() && gyro->finished()) && std::chrono::steady_clock::now() < t_end) {
    cam->doProcess();
    gyro->doProcess();
    for (auto* s : {cam_base.get(), gyro_base.get()}) {
      auto obs = s->getObservations();
      all.insert(obs.begin(), obs.end());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_TRUE(cam->finished());
  ASSERT_TRUE(gyro->finished());
  EXPECT_EQ(gyro->samplesEmitted(), 50);
  // Real time on a shared machine may skip a frame, never invent one.
  EXPECT_EQ(cam->framesEmitted() + cam->framesSkipped(), 10);
  EXPECT_GE(cam->framesEmitted(), 5);

  // Same data as the offline model: frame images and gyro samples for the seed.
  const Scenario sc = Scenario::load(scenario);
  SkySimulator sim(sc, sc.seed);
  GyroStream gs(sc, sc.seed);
  // Stamped on the scenario's clock (its start_time + t), exactly as `simulate` stamps: the
  // sky is rendered for that date, so the stamps must carry it (not the wall clock's).
  const auto start = sc.timestamp(0);
  int cams = 0, gyros = 0, truths = 0;
  for (const auto& [stamp, ser] : all) {
    const double t = std::chrono::duration<double>(stamp - start).count();
    ASSERT_GE(t, -1e-9) << "stamped before the scenario's start (the wall clock?)";
    ASSERT_LE(t, sc.duration_s + 1e-9) << "stamped after the scenario's end (the wall clock?)";
    if (auto img = std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(ser)) {
      ++cams;
      const int k = static_cast<int>(std::lround(t * sc.frame_rate_hz));
      EXPECT_EQ(stamp, sc.timestamp(sc.frameTime(k)));
      EXPECT_EQ(cv::norm(img->image.asCvMatRef(), sim.frame(k).image, cv::NORM_INF), 0.0);
      EXPECT_EQ(img->sensorLabel, "CAMERA");
    } else if (auto imu = std::dynamic_pointer_cast<mrpt::obs::CObservationIMU>(ser)) {
      GyroSample g;
      ASSERT_TRUE(gs.next(g));
      EXPECT_EQ(stamp, sc.timestamp(g.t));
      EXPECT_EQ(rateFromObservation(*imu), g.rate);
      ++gyros;
    } else if (std::dynamic_pointer_cast<mrpt::obs::CObservation6DFeatures>(ser)) {
      ++truths;
    }
  }
  EXPECT_EQ(cams, cam->framesEmitted());
  EXPECT_EQ(truths, cams);
  EXPECT_EQ(gyros, 50);
}

TEST(SimulatedSensors, MissingScenarioKeyIsAnInputError) {
  registerSimulatedSensors();
  auto s = mrpt::hwdrivers::CGenericSensor::createSensorPtr("CSimulatedStarCamera");
  mrpt::config::CConfigFileMemory cfg("[CAM]\nprocess_rate = 10\n");
  EXPECT_THROW(s->loadConfig(cfg, "CAM"), std::exception);
}

}  // namespace
}  // namespace st
