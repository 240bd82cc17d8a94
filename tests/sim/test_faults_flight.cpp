// The simulator's flight faults (issue 18 item 6): a stuck or noisy gyro axis, gyro spikes,
// frozen images and camera clock jumps (sensors/sim/faults.hpp). The replays of their
// scenarios are in tests/app/test_faults_replay.cpp.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>

#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "sensors/sim/faults.hpp"

namespace st {
namespace {

TEST(FlightFaults, ParsedFromIniWithErrorsNamingTheKey) {
  mrpt::config::CConfigFileMemory cfg(
      "[f]\ngyro_stuck_axis = 1\ngyro_noisy_axis = 2\ngyro_noise_deg_s = 0.5\n"
      "gyro_fault_start_s = 3\ngyro_fault_end_s = 4\ngyro_spikes_per_s = 2\n"
      "frozen_s = 8 10\ncamera_time_jump_s = 8 1.0 12 -1.0\n"
      "[bad]\ngyro_stuck_axis = 3\n[bad2]\nfrozen_s = 10 8\n");
  const FaultParams f = FaultParams::fromConfig(cfg, "f");
  EXPECT_EQ(f.gyro_stuck_axis, 1);
  EXPECT_EQ(f.gyro_noisy_axis, 2);
  EXPECT_DOUBLE_EQ(f.gyro_fault_end_s, 4.0);
  ASSERT_EQ(f.camera_time_jumps.size(), 2u);
  EXPECT_EQ(f.camera_time_jumps[1], std::make_pair(12.0, -1.0));
  try {
    FaultParams::fromConfig(cfg, "bad");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("gyro_stuck_axis"), std::string::npos) << e.what();
  }
  EXPECT_THROW(FaultParams::fromConfig(cfg, "bad2"), InputError);
}

TEST(FlightFaults, StuckAxisHoldsItsLastReadingOnlyDuringTheFault) {
  FaultParams f;
  f.gyro_stuck_axis = 1;
  f.gyro_fault_start_s = 1.0;
  f.gyro_fault_end_s = 2.0;
  Vec3 held = Vec3::Zero();
  for (int j = 1; j <= 300; ++j) {
    const double t = j / 100.0;
    const Vec3 truth(0.01 * j, 0.02 * j, 0.03 * j);
    Vec3 rate = truth;
    applyGyroFaults(rate, held, f, 7, j, t, 100.0);
    if (t >= 1.0 && t < 2.0) {
      EXPECT_DOUBLE_EQ(rate.y(), 0.02 * 99) << t;  // the reading of the last sample before
      EXPECT_DOUBLE_EQ(rate.x(), truth.x());
    } else {
      EXPECT_EQ(rate, truth) << t;
    }
  }
}

TEST(FlightFaults, NoisyAxisHasTheConfiguredSigmaAndSpikesTheirRate) {
  FaultParams f;
  f.gyro_noisy_axis = 0;
  f.gyro_noise_deg_s = 2.0;
  Vec3 held = Vec3::Zero();
  const int n = 20000;
  double s2 = 0;
  for (int j = 1; j <= n; ++j) {
    Vec3 rate = Vec3::Zero();
    applyGyroFaults(rate, held, f, 3, j, j / 100.0, 100.0);
    EXPECT_EQ(rate.y(), 0.0);
    s2 += rate.x() * rate.x();
  }
  // The sample standard deviation of n normal draws: relative sigma 1/sqrt(2n) = 0.5 %; 5 sigma.
  EXPECT_NEAR(rad2deg(std::sqrt(s2 / n)), 2.0, 2.0 * 5 * std::sqrt(0.5 / n));

  FaultParams g;
  g.gyro_spikes_per_s = 2.0;
  g.gyro_spike_deg_s = 5.0;
  int spikes = 0;
  for (int j = 1; j <= n; ++j) {
    Vec3 rate = Vec3::Zero();
    applyGyroFaults(rate, held, g, 3, j, j / 100.0, 100.0);
    if (rate != Vec3::Zero()) {
      ++spikes;
      EXPECT_NEAR(rad2deg(rate.cwiseAbs().maxCoeff()), 5.0, 1e-9);
    }
  }
  // 200 s at 2 per second: Poisson mean 400, sigma 20; 5 sigma.
  EXPECT_NEAR(spikes, 400, 100);
}

TEST(FlightFaults, FrozenFramesShowTheImageBeforeTheIntervalAndClockJumpsAddUp) {
  FaultParams f;
  f.frozen = {{0.8, 1.0}};
  EXPECT_EQ(frozenImageSource(f, 7, 0.7, 10.0), 7);
  EXPECT_EQ(frozenImageSource(f, 8, 0.8, 10.0), 7);
  EXPECT_EQ(frozenImageSource(f, 9, 0.9, 10.0), 7);
  EXPECT_EQ(frozenImageSource(f, 10, 1.0, 10.0), 10);
  f.camera_time_jumps = {{8.0, 1.0}, {12.0, -1.0}};
  EXPECT_DOUBLE_EQ(cameraClock(f, 7.9), 7.9);
  EXPECT_DOUBLE_EQ(cameraClock(f, 8.0), 9.0);
  EXPECT_DOUBLE_EQ(cameraClock(f, 11.9), 12.9);
  EXPECT_DOUBLE_EQ(cameraClock(f, 12.0), 12.0);
}

}  // namespace
}  // namespace st
