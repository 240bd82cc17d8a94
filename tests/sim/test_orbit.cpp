// The observer's orbit (sensors/sim/orbit.hpp) and what a scenario with one produces: the sky
// rendered aberrated by its velocity and VELOCITY observations that carry it (issue 16 item 3).
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CRawlog.h>

#include <chrono>
#include <cmath>
#include <map>
#include <string>

#include "common/aberration.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "sensors/mrpt/rawlog_contract.hpp"
#include "sensors/sim/rawlog_writer.hpp"
#include "sensors/sim/scenario.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

TEST(Orbit, CircularOrbitSpeedPeriodAndVelocityAreKepler) {
  CircularOrbit o;  // 600 km polar (seed 003's Oersted)
  EXPECT_NEAR(o.speedKmS(), 7.5576, 1e-3);
  EXPECT_NEAR(o.periodS() / 60, 96.69, 0.01);
  // 5.2": seed 003 quotes 5.7" for 8.3 km/s; both are v / c.
  EXPECT_NEAR(rad2arcsec(o.speedKmS() / kSpeedOfLightKmS), 5.20, 0.01);
  o.inclination_deg = 51.6;
  o.raan_deg = 30;
  o.arg_latitude_deg = 10;
  for (double t : {0.0, 100.0, 2000.0}) {
    const Vec3 r = o.positionAt(t), v = o.velocityAt(t);
    EXPECT_NEAR(r.norm(), o.radiusKm(), 1e-9);
    EXPECT_NEAR(v.norm(), o.speedKmS(), 1e-12);
    EXPECT_NEAR(r.dot(v), 0, 1e-9);
    // The velocity is the position's derivative (central difference, 1 ms).
    const Vec3 d = (o.positionAt(t + 1e-3) - o.positionAt(t - 1e-3)) / 2e-3;
    EXPECT_LT((d - v).norm(), 1e-6) << t;
    // Inclination: the orbit normal's angle to the pole.
    EXPECT_NEAR(rad2deg(std::acos(r.cross(v).normalized().z())), 51.6, 1e-9);
  }
  EXPECT_NEAR(o.positionAt(0).z(), o.radiusKm() * std::sin(deg2rad(10)) * std::sin(deg2rad(51.6)), 1e-9);
}

std::string scenarioText(const std::string& orbit) {
  return R"(
[scenario]
duration_s = 2.0
frame_rate_hz = 2
start_time = 2025-03-20T00:00:00
seed = 3
[camera]
resolution = [256 256]
fov_deg = 15
[sensor]
exposure_s = 0.1
bit_depth = 8
[motion]
type = slew
ra_deg = 90
dec_deg = 0
rate_deg_s = 0 0 0
)" + orbit;
}

Scenario scenarioOf(const std::string& text) {
  mrpt::config::CConfigFileMemory cfg(text);
  return Scenario::fromConfig(cfg, "orbit.ini");
}

// The renderer moves every star by the aberration of the orbit's velocity: the true pixel of
// each star with the orbit minus without it is the projection of applyAberration's shift
// (about 0.025 px here: 5.2" at 211"/px).
TEST(Orbit, TheSkyIsRenderedAtTheApparentDirections) {
  const Scenario still = scenarioOf(scenarioText(""));
  const Scenario moving = scenarioOf(scenarioText("[orbit]\naltitude_km = 600\ninclination_deg = 90\n"));
  ASSERT_TRUE(moving.orbit);
  SkySimulator a(still, 3), b(moving, 3);
  const SimFrame fa = a.frame(1), fb = b.frame(1);
  ASSERT_GE(fa.truth.size(), 3u);
  ASSERT_EQ(fa.truth.size(), fb.truth.size());
  const Vec3 v = moving.observerVelocity(fb.t);
  const Mat3 R_ci = fa.q_ib.toRotationMatrix().transpose();
  const CameraModel& cam = still.camera;
  for (std::size_t k = 0; k < fa.truth.size(); ++k) {
    ASSERT_EQ(fa.truth[k].id, fb.truth[k].id);
    const Vec3 u = (fa.q_ib.toRotationMatrix() * cam.pixelToVector(fa.truth[k].px)).normalized();
    const auto expected = cam.vectorToPixel(R_ci * applyAberration(u, v));
    ASSERT_TRUE(expected);
    const Vec2 shift = fb.truth[k].px - fa.truth[k].px;
    EXPECT_GT(shift.norm(), 0.02) << k;
    EXPECT_LT((fb.truth[k].px - *expected).norm(), 1e-6) << k;
  }
}

TEST(Orbit, RawlogCarriesVelocitySamplesInTimeOrder) {
  const Scenario sc = scenarioOf(
      scenarioText("[orbit]\naltitude_km = 600\ninclination_deg = 97\nvelocity_rate_hz = 2\n"));
  const std::string dir = test::makeTempDir("orbit_rawlog");
  SimulateOptions opts;
  opts.progress = false;
  const SimulateSummary s = simulateToRawlog(sc, dir + "/o.rawlog", opts);
  EXPECT_EQ(s.velocity_samples, 5);  // t = 0, 0.5, 1, 1.5, 2
  mrpt::obs::CRawlog log;
  ASSERT_TRUE(log.loadFromRawLogFile(dir + "/o.rawlog"));
  std::map<std::string, int> count;
  mrpt::Clock::time_point prev{};
  for (std::size_t i = 0; i < log.size(); ++i) {
    const auto obs = log.getAsObservation(i);
    EXPECT_GE(obs->timestamp, prev);
    prev = obs->timestamp;
    ++count[obs->sensorLabel];
    if (obs->sensorLabel != "VELOCITY") continue;
    auto imu = std::dynamic_pointer_cast<mrpt::obs::CObservationIMU>(obs);
    ASSERT_TRUE(imu);
    const auto v = velocityFromObservation(*imu);
    ASSERT_TRUE(v);
    const double t = std::chrono::duration<double>(obs->timestamp - sc.timestamp(0)).count();
    EXPECT_LT((*v - sc.observerVelocity(t)).norm(), 1e-9) << t;
  }
  EXPECT_EQ(count["VELOCITY"], 5);
  EXPECT_EQ(count["CAMERA"], 4);
}

TEST(Orbit, BadOrbitKeysNameTheKey) {
  for (const std::string bad : {"altitude_km = -5", "inclination_deg = 200", "velocity_rate_hz = -1",
                                "altitud_km = 600"}) {
    try {
      scenarioOf(scenarioText("[orbit]\n" + bad + "\n"));
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      const std::string key = bad.substr(0, bad.find(' '));
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("orbit"), std::string::npos) << e.what();
    }
  }
  // A named section that does not exist is an error, not "no orbit".
  EXPECT_THROW(scenarioOf(scenarioText("").insert(12, "orbit_section = leo\n")), InputError);
}

}  // namespace
}  // namespace st
