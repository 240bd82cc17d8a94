// Faults and clutter: false stars, spikes, extended object, blinding glow, dropped frames.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>

#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "sensors/sim/faults.hpp"
#include "sensors/sim/motion.hpp"
#include "sensors/sim/scenario.hpp"

namespace st {
namespace {

const CameraModel kCam = CameraModel::fromFov(200, 150, deg2rad(10.0));

TEST(Faults, ParsedFromIniWithErrorsNamingTheKey) {
  mrpt::config::CConfigFileMemory cfg(
      "[f]\nfalse_stars = 4\nspikes_per_frame = 2.5\nblinding_e_px_s = 1000\n"
      "blinding_center_px = 10 -20\ndropout_s = 1 2 5 6\nmissing_star_fraction = 0.1\n"
      "[bad]\nmissing_star_fraction = 1.5\n[bad2]\ndropout_s = 1 2 3\n");
  const FaultParams f = FaultParams::fromConfig(cfg, "f");
  EXPECT_EQ(f.false_stars, 4);
  EXPECT_DOUBLE_EQ(f.spikes_per_frame, 2.5);
  EXPECT_EQ(f.blinding_center_px, Vec2(10, -20));
  ASSERT_EQ(f.dropouts.size(), 2u);
  EXPECT_EQ(f.dropouts[1], std::make_pair(5.0, 6.0));
  try {
    FaultParams::fromConfig(cfg, "bad");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("missing_star_fraction"), std::string::npos);
  }
  EXPECT_THROW(FaultParams::fromConfig(cfg, "bad2"), InputError);
}

TEST(Faults, FalseSourcesAreMetAlongTheTrajectoryAndFixedInertially) {
  FaultParams f;
  f.false_stars = 5;
  f.extended_objects = 1;
  const SlewMotion motion(attitudeFromRaDecRoll({1.0, 0.3, 0.0}), Vec3(0, deg2rad(2.0), 0));
  const auto a = placeFalseSources(f, kCam, motion, 10.0, 1.0, 42);
  const auto b = placeFalseSources(f, kCam, motion, 10.0, 1.0, 42);
  ASSERT_EQ(a.size(), 6u);
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].u_i, b[i].u_i);
  EXPECT_DOUBLE_EQ(a[5].sigma_px, f.extended_sigma_px);
  // Each is inside the frame at some time of the run.
  for (const ExtraSource& s : a) {
    bool seen = false;
    for (double t = 0; t <= 10.0 && !seen; t += 0.05)
      seen = kCam.isVectorInImage(motion.attitude(t).toRotationMatrix().transpose() * s.u_i);
    EXPECT_TRUE(seen);
  }
}

TEST(Faults, SpikesDepositTheirChargeInSharpTracks) {
  FaultParams f;
  f.spikes_per_frame = 50;
  f.spike_e_min = f.spike_e_max = 1000;
  f.spike_length_max_px = 5;
  cv::Mat e(150, 200, CV_64FC1, cv::Scalar(0));
  std::mt19937_64 rng(1);
  const int n = addSpikes(e, f, rng);
  EXPECT_GT(n, 20);
  // Charge is conserved except for tracks leaving the frame.
  EXPECT_LE(cv::sum(e)[0], n * 1000.0 + 1e-6);
  EXPECT_GT(cv::sum(e)[0], 0.8 * n * 1000.0);
  // Sharp: a track covers at most ~length + 1 pixels.
  EXPECT_LE(cv::countNonZero(e), n * 7);
}

TEST(Faults, BlindingRaisesTheBackgroundNearItsCentreDuringItsWindow) {
  FaultParams f;
  f.blinding_e_px_s = 10000;
  f.blinding_center_px = Vec2(-10, 75);
  f.blinding_radius_px = 40;
  f.blinding_start_s = 1.0;
  f.blinding_end_s = 2.0;
  cv::Mat e(150, 200, CV_64FC1, cv::Scalar(0));
  addBlinding(e, f, 0.5, 0.1);
  EXPECT_EQ(cv::countNonZero(e), 0);
  addBlinding(e, f, 1.5, 0.1);
  EXPECT_NEAR(e.at<double>(75, 0), 1000.0 / (1 + 100.0 / 1600.0), 1e-9);
  EXPECT_GT(e.at<double>(75, 0), 20 * e.at<double>(75, 199));
}

TEST(Faults, DroppedFramesFromIntervalsAndProbability) {
  FaultParams f;
  f.dropouts = {{1.0, 1.5}};
  EXPECT_TRUE(isFrameDropped(f, 1, 10, 1.0));
  EXPECT_FALSE(isFrameDropped(f, 1, 15, 1.5));
  f.drop_frame_probability = 0.25;
  int dropped = 0;
  for (int k = 0; k < 4000; ++k) dropped += isFrameDropped(f, 9, k, 100.0 + k);
  EXPECT_NEAR(dropped, 1000, 5 * std::sqrt(4000 * 0.25 * 0.75));
}

TEST(Faults, FalseStarsAndExtendedObjectAreInTheImageButNotInTheTruth) {
  mrpt::config::CConfigFileMemory cfg(R"(
[scenario]
duration_s = 0.1
[camera]
resolution = [200 150]
fov_deg = 10
[sensor]
gain_e_per_adu = 2
bit_depth = 16
read_noise_e = 0.001
sky_e_px_s = 0
dark_current_e_px_s = 0
[motion]
type = hold
ra_deg = 10
dec_deg = 10
[faults]
false_stars = 3
false_star_mag_min = 2
false_star_mag_max = 2
extended_objects = 1
extended_mag = 1
extended_sigma_px = 8
)");
  const Scenario sc = Scenario::fromConfig(cfg, "faults.ini");
  SkySimulator sim(sc, 4, std::make_shared<ListStarSource>(std::vector<SkyStar>{}));
  const SimFrame f = sim.frame(0);
  EXPECT_TRUE(f.truth.empty());  // no catalog stars, and clutter is never truth
  cv::Mat d;
  f.image.convertTo(d, CV_64F);
  const double bias = sc.sensor.bias_adu;
  // All clutter light arrives (sources placed away from the edges): 3 x mag 2 + 1 x mag 1.
  const double expected = (3 * sc.sensor.starElectrons(2) + sc.sensor.starElectrons(1)) / 2.0;
  EXPECT_NEAR((cv::sum(d)[0] - bias * d.total()) / expected, 1.0, 0.02);
}

}  // namespace
}  // namespace st
