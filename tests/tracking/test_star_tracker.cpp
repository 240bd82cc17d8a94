// StarTracker on short simulated sequences (SIM renderer + detector, the committed
// Hipparcos subset): lost-in-space start, frame-to-frame tracking by rate match, by gyro, by
// an external prediction, stars entering the FOV, fall-back to lost-in-space, rejection of a
// wrong prediction, and the body frame of a mounted camera.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "common/chi_square.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "sensors/tracking/star_tracker.hpp"
#include "tests/tracking/tracker_scoring.hpp"
#include "tests/tracking/tracker_sim.hpp"

namespace st {
namespace {

using test::FrameSimulator;
using namespace test::scoring;

TEST(StarTracker, LostInSpaceThenRateMatchTrackingDuringASlew) {
  const SlewMotion motion(startAttitude(), Vec3(deg2rad(0.8), deg2rad(-0.5), deg2rad(0.3)));
  FrameSimulator sim(101);
  StarTracker pipe(test::simDatabase(), test::simCamera(), test::simTrackerOptions());
  RunStats s;
  std::set<uint32_t> first_tracked_truth;
  std::vector<StarTrackerMode> modes;
  for (int k = 0; k < 60; ++k) {
    const auto f = sim.frame(motion, 0.1 * k);
    const FrameResult o = pipe.process(f.image, f.t_s);
    modes.push_back(o.mode);
    score(o, f, f.q_ib, s);
    if (k == 2)
      for (const TrueStar& t : f.stars) first_tracked_truth.insert(t.id);
    if (k >= 2) {
      EXPECT_EQ(o.mode, StarTrackerMode::kTracking) << "frame " << k << ": " << o.detail;
    }
  }
  // Lost-in-space twice (no rate yet), then the rate of the last two fixes carries it.
  EXPECT_EQ(modes[0], StarTrackerMode::kLostInSpace);
  EXPECT_EQ(modes[1], StarTrackerMode::kLostInSpace);
  EXPECT_EQ(s.modes[StarTrackerMode::kTracking], 58);
  expectRightStars(s);
  expectNotOptimistic(s);
  // Stars that entered the field after frame 2 were picked up and identified.
  int entered = 0;
  for (uint32_t id : s.ids_seen) entered += first_tracked_truth.count(id) == 0;
  EXPECT_GT(entered, 3);
  std::cout << "[ info ] slew 1 deg/s: " << s.matched << " matches, max error "
            << s.max_error_arcsec << " arcsec, mean NEES " << meanNees(s) << ", " << entered
            << " stars entered the FOV\n";
}

TEST(StarTracker, GyroRateTracksThroughAnAcceleratingSlewFromTheSecondFrame) {
  // 0 -> 3 deg/s at 1.5 deg/s^2, then coast: the rate match would lag, the gyro does not.
  const SlewAccelMotion motion(startAttitude(), Vec3(0.3, 1.0, 0.2), deg2rad(3.0), deg2rad(1.5),
                               2.0, 0.2);
  FrameSimulator sim(202);
  TrackerOptions opts = test::simTrackerOptions();
  opts.gyro_sigma = 2e-4;
  StarTracker pipe(test::simDatabase(), test::simCamera(), opts);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n01;
  RunStats s;
  for (int k = 0; k < 40; ++k) {
    const double t = 0.1 * k;
    FrameInputs in;
    if (k > 0) {
      // Mean rate over the interval (midpoint rule) + white noise of gyro_sigma / 2.
      const Vec3 w = motion.rateBody(t - 0.05) + 1e-4 * Vec3(n01(rng), n01(rng), n01(rng));
      in.rate_body = w;
    }
    const auto f = sim.frame(motion, t);
    const FrameResult o = pipe.process(f.image, f.t_s, in);
    score(o, f, f.q_ib, s);
    // Issue 7's criterion: no lost-in-space after the first frame. A single frame may fail
    // (a prediction check rejecting a good fix at its false-alarm rate), never
    // max_failed_frames in a row.
    if (k == 0) {
      EXPECT_EQ(o.mode, StarTrackerMode::kLostInSpace) << o.detail;
    } else {
      EXPECT_NE(o.mode, StarTrackerMode::kLostInSpace) << "frame " << k;
      EXPECT_FALSE(pipe.isLost()) << "frame " << k << ": " << o.detail;
      if (o.mode == StarTrackerMode::kFailed) {
        std::cout << "[ info ] frame " << k << " failed: " << o.detail << "\n";
      }
    }
  }
  expectRightStars(s);
  std::cout << "[ info ] slew up to 3 deg/s, gyro: " << s.matched << " matches, max error "
            << s.max_error_arcsec << " arcsec, mean NEES " << meanNees(s) << "\n";
}

// The reported covariance is consistent in the chi-square sense during constant-rate slews
// with a gyro (noise as the pipeline's gyro_sigma): 1 deg/s (2.5 px streaks) and 3 deg/s
// (15 px streaks, whose faint fragments full-frame detection finds; lost-in-space re-measures
// them over the whole streak the gyro rate predicts, or, in the first frame without a rate,
// the streak the blobs' shapes give).
TEST(StarTracker, CovarianceIsConsistentDuringSlews) {
  for (const double rate_deg_s : {1.0, 3.0}) {
    SCOPED_TRACE(rate_deg_s);
    const SlewMotion motion(startAttitude(),
                            deg2rad(rate_deg_s) * Vec3(0.8, -0.5, 0.3).normalized());
    FrameSimulator sim(707);
    const TrackerOptions opts = test::simTrackerOptions();
    StarTracker pipe(test::simDatabase(), test::simCamera(), opts);
    std::mt19937_64 rng(17);
    std::normal_distribution<double> n01;
    RunStats s;
    for (int k = 0; k < 60; ++k) {
      FrameInputs in;
      if (k > 0) {
        in.rate_body =
            motion.rateBody(0.1 * k) + opts.gyro_sigma * Vec3(n01(rng), n01(rng), n01(rng));
      }
      const auto f = sim.frame(motion, 0.1 * k);
      const FrameResult o = pipe.process(f.image, f.t_s, in);
      if (k >= 1) {
        EXPECT_TRUE(o.hasAttitude()) << "frame " << k << ": " << o.detail;
      }
      score(o, f, f.q_ib, s);
    }
    expectRightStars(s);
    expectConsistent(s);
    std::cout << "[ info ] " << rate_deg_s << " deg/s with a gyro: " << s.nees.size()
              << " fixes, mean NEES " << meanNees(s) << ", max error " << s.max_error_arcsec
              << " arcsec\n";
  }
}

TEST(StarTracker, LostInSpaceMeasuresStreaksFromTheirShapesWithoutARate) {
  // The first frame of a fast slew, no gyro: faint 10-15 px streaks break into fragments
  // whose centroids sit up to half a streak off. The streak is estimated from the brightest
  // blobs' moments and every star re-measured over it.
  int solved = 0;
  RunStats s;
  for (int k = 0; k < 6; ++k) {
    const double az = 2.0 * M_PI * k / 6.0;
    const double rate = deg2rad(2.0 + 0.2 * k);
    const SlewMotion motion(
        attitudeFromRaDecRoll({deg2rad(84.0 + 25.0 * k), deg2rad(-2.0 + 6.0 * k), deg2rad(25.0)}),
        rate * Vec3(std::cos(az), std::sin(az), 0.05));
    FrameSimulator sim(900 + k);
    StarTracker pipe(test::simDatabase(), test::simCamera(), test::simTrackerOptions());
    const auto f = sim.frame(motion, 0.0);
    const FrameResult o = pipe.process(f.image, f.t_s);
    solved += o.mode == StarTrackerMode::kLostInSpace;
    if (o.mode != StarTrackerMode::kLostInSpace) {
      std::cout << "[ info ] slew " << k << ": " << o.detail << "\n";
    }
    score(o, f, f.q_ib, s);
  }
  // Measured: 5 of 6 (the sixth is refused by verification: a false-match probability of
  // 0.03, never a wrong attitude); without the shape estimate 0 of 6.
  EXPECT_GE(solved, 5);
  expectRightStars(s);
  for (double v : s.nees) EXPECT_LT(v, chi2Quantile(3, 0.999)) << "a fix outside its covariance";
  std::cout << "[ info ] streaked first frames without a rate: " << solved << "/6 solved, "
            << s.matched << " stars, mean NEES " << meanNees(s) << "\n";
}

TEST(StarTracker, ExternalPredictionIsUsedFromTheNextFrame) {
  const SlewMotion motion(startAttitude(), Vec3(deg2rad(-0.5), deg2rad(1.0), 0.0));
  FrameSimulator sim(303);
  StarTracker pipe(test::simDatabase(), test::simCamera(), test::simTrackerOptions());
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n01;
  const double sigma = arcsec2rad(60.0);
  RunStats s;
  for (int k = 0; k < 20; ++k) {
    const double t = 0.1 * k;
    FrameInputs in;
    if (k > 0) {
      AttitudePrediction p;  // truth with an error drawn from its covariance
      p.q_ib = motion.attitude(t) * quatExp(sigma * Vec3(n01(rng), n01(rng), n01(rng)));
      p.cov_body = sigma * sigma * Mat3::Identity();
      p.rate_body = motion.rateBody(t);
      in.prediction = p;
    }
    const auto f = sim.frame(motion, t);
    const FrameResult o = pipe.process(f.image, f.t_s, in);
    score(o, f, f.q_ib, s);
    EXPECT_EQ(o.mode, k == 0 ? StarTrackerMode::kLostInSpace : StarTrackerMode::kTracking)
        << "frame " << k << ": " << o.detail;
  }
  expectRightStars(s);
}

// With a gyro rate the prediction does not rest on our own fixes alone: a few frames without
// stars (a blinded camera) are a transient, so the tracker waits max_failed_frames before it
// drops to lost-in-space. (Without an independent rate it goes at once:
// TrackerCamera.AnUnrelatedFrameGoesToLostInSpaceAtOnceWithoutAnIndependentRate.)
TEST(StarTracker, WithAGyroFallsBackToLostInSpaceAfterFailedFramesAndRecovers) {
  const SlewMotion motion(startAttitude(), Vec3(0.0, deg2rad(0.5), 0.0));
  FrameSimulator sim(404);
  TrackerOptions opts = test::simTrackerOptions();
  opts.max_failed_frames = 3;
  StarTracker pipe(test::simDatabase(), test::simCamera(), opts);
  std::vector<StarTrackerMode> modes;
  RunStats s;
  for (int k = 0; k < 14; ++k) {
    const double t = 0.1 * k;
    const bool blind = k >= 4 && k < 8;  // four frames without stars
    const auto f = blind ? sim.darkFrame(t) : sim.frame(motion, t);
    FrameInputs in;
    in.rate_body = motion.rateBody(t);
    const FrameResult o = pipe.process(f.image, f.t_s, in);
    modes.push_back(o.mode);
    if (!blind) score(o, f, f.q_ib, s);
    EXPECT_EQ(o.failure == FrameFailure::kNone, o.hasAttitude()) << "frame " << k;
    EXPECT_EQ(o.fell_back_to_lost_in_space, k == 6) << "frame " << k << ": " << o.detail;
    if (k == 6) {
      EXPECT_TRUE(pipe.isLost()) << "3 failed tracking frames must drop to lost-in-space";
      EXPECT_NE(o.detail.find("back to lost-in-space"), std::string::npos) << o.detail;
    }
    if (k == 5) {
      EXPECT_FALSE(pipe.isLost());
    }
  }
  // The gyro carries the first fix to the next frame: tracking from the second frame on.
  const std::vector<StarTrackerMode> expected = {
      StarTrackerMode::kLostInSpace, StarTrackerMode::kTracking, StarTrackerMode::kTracking,
      StarTrackerMode::kTracking,    StarTrackerMode::kFailed,   StarTrackerMode::kFailed,
      StarTrackerMode::kFailed,      StarTrackerMode::kFailed,   StarTrackerMode::kLostInSpace,
      StarTrackerMode::kTracking,    StarTrackerMode::kTracking, StarTrackerMode::kTracking,
      StarTrackerMode::kTracking,    StarTrackerMode::kTracking};
  for (std::size_t k = 0; k < expected.size(); ++k) {
    EXPECT_EQ(toString(modes[k]), std::string(toString(expected[k]))) << "frame " << k;
  }
  expectRightStars(s);
}

// A prediction 0.3 deg off that claims 20": its windows hold no star. The frame is never
// misidentified: it is solved lost-in-space in the same frame (TrackerOptions::
// reacquire_in_frame), or with that off it fails.
TEST(StarTracker, AWrongPredictionFailsInsteadOfMisidentifying) {
  const HoldMotion motion(startAttitude());
  for (const bool reacquire : {false, true}) {
    SCOPED_TRACE(reacquire ? "re-acquisition in the frame" : "no re-acquisition in the frame");
    FrameSimulator sim(505);
    TrackerOptions opts = test::simTrackerOptions();
    opts.reacquire_in_frame = reacquire;
    StarTracker pipe(test::simDatabase(), test::simCamera(), opts);
    RunStats s;
    for (int k = 0; k < 6; ++k) {
      FrameInputs in;
      if (k > 0) {
        AttitudePrediction p;  // 0.3 deg off, claiming 20 arcsec
        p.q_ib = motion.attitude(0) * quatExp(Vec3(deg2rad(0.2), deg2rad(-0.2), deg2rad(0.1)));
        p.cov_body = std::pow(arcsec2rad(20.0), 2) * Mat3::Identity();
        in.prediction = p;
      }
      const auto f = sim.frame(motion, 0.1 * k);
      const FrameResult o = pipe.process(f.image, f.t_s, in);
      score(o, f, f.q_ib, s);
      if (k >= 1 && k <= 3 && !reacquire) {
        EXPECT_EQ(o.mode, StarTrackerMode::kFailed) << "frame " << k << ": " << o.detail;
        EXPECT_EQ(o.prediction, PredictionSource::kExternal);
        EXPECT_TRUE(o.failure == FrameFailure::kTooFewInGate ||
                    o.failure == FrameFailure::kInconsistentPrediction ||
                    o.failure == FrameFailure::kResiduals)
            << toString(o.failure);
      }
      if (k >= 1 && reacquire) {
        EXPECT_TRUE(reacquiredInFrame(o.mode, o.detail)) << "frame " << k << ": " << o.detail;
      }
    }
    EXPECT_TRUE(s.modes[StarTrackerMode::kLostInSpace] >= 2) << "recovered by lost-in-space";
    EXPECT_EQ(s.misidentified, 0);
  }

  // Teeth: the same prediction told with an honest covariance tracks.
  StarTracker honest(test::simDatabase(), test::simCamera(), test::simTrackerOptions());
  FrameSimulator sim2(506);
  auto f0 = sim2.frame(motion, 0);
  ASSERT_EQ(honest.process(f0.image, f0.t_s).mode, StarTrackerMode::kLostInSpace);
  AttitudePrediction p;
  p.q_ib = motion.attitude(0) * quatExp(Vec3(deg2rad(0.2), deg2rad(-0.2), deg2rad(0.1)));
  p.cov_body = std::pow(deg2rad(0.3), 2) * Mat3::Identity();
  FrameInputs in;
  in.prediction = p;
  auto f1 = sim2.frame(motion, 0.1);
  const FrameResult o1 = honest.process(f1.image, f1.t_s, in);
  EXPECT_EQ(o1.mode, StarTrackerMode::kTracking) << o1.detail;
}

TEST(StarTracker, MountedCameraReportsTheBodyAttitude) {
  // Camera rotated on the vehicle: q_ib = q_ic (x) q_cb, covariance rotated into the body.
  TrackerOptions opts = test::simTrackerOptions();
  // Yaw 90 deg, pitch 10 deg (MRPT's CPose3D order: R = Rz(yaw) Ry(pitch) Rx(roll)).
  const Mat3 R_bc = (Eigen::AngleAxisd(deg2rad(90.0), Vec3::UnitZ()) *
                     Eigen::AngleAxisd(deg2rad(10.0), Vec3::UnitY()))
                        .toRotationMatrix();
  opts.R_body_cam = R_bc;
  const Vec3 w_body(deg2rad(0.5), deg2rad(0.2), deg2rad(-0.4));
  // The camera's motion for a body slewing at w_body: w_cam = R_cb w_body.
  const Quat q_ic0 = startAttitude();
  const SlewMotion motion_cam(q_ic0, R_bc.transpose() * w_body);
  FrameSimulator sim(606);
  StarTracker pipe(test::simDatabase(), test::simCamera(), opts);
  RunStats s;
  for (int k = 0; k < 12; ++k) {
    const double t = 0.1 * k;
    FrameInputs in;
    if (k > 0) in.rate_body = w_body;
    const auto f = sim.frame(motion_cam, t);
    const FrameResult o = pipe.process(f.image, f.t_s, in);
    const Quat q_ib_true = canonical(f.q_ib * Quat(R_bc.transpose()));
    score(o, f, q_ib_true, s);
    ASSERT_TRUE(o.hasAttitude()) << o.detail;
    EXPECT_LT(rad2arcsec(attitudeError(o.q_ib, q_ib_true).total), 60.0);
  }
  EXPECT_EQ(s.misidentified, 0);
  EXPECT_EQ(s.modes[StarTrackerMode::kTracking], 11);
  // Teeth: the camera attitude is not the body attitude here.
  const auto f = sim.frame(motion_cam, 1.2);
  const FrameResult o = pipe.process(f.image, f.t_s, FrameInputs{});
  EXPECT_GT(rad2deg(attitudeError(o.q_ib, f.q_ib).total), 45.0);
}

TEST(StarTracker, ForcedLostInSpaceForgetsTheTrackingState) {
  const SlewMotion motion(startAttitude(), Vec3(deg2rad(0.3), 0.0, 0.0));
  FrameSimulator sim(808);
  StarTracker pipe(test::simDatabase(), test::simCamera(), test::simTrackerOptions());
  FrameInputs in;
  in.rate_body = motion.rateBody(0.0);
  for (int k = 0; k < 3; ++k) {
    const auto f = sim.frame(motion, 0.1 * k);
    in.force_lost_in_space = k == 2;
    const FrameResult o = pipe.process(f.image, f.t_s, in);
    EXPECT_EQ(o.mode, k == 1 ? StarTrackerMode::kTracking : StarTrackerMode::kLostInSpace)
        << "frame " << k << ": " << o.detail;
    EXPECT_EQ(o.prediction, k == 1 ? PredictionSource::kGyro : PredictionSource::kNone);
  }
}

TEST(StarTracker, BadOptionsAreInputErrors) {
  TrackerOptions o;
  o.lis_algorithm = "no-such-algorithm";
  EXPECT_THROW(StarTracker(test::simDatabase(), test::simCamera(), o), InputError);
  o = {};
  o.solver = "nope";
  EXPECT_THROW(StarTracker(test::simDatabase(), test::simCamera(), o), InputError);
  o = {};
  o.max_failed_frames = 0;
  EXPECT_THROW(StarTracker(test::simDatabase(), test::simCamera(), o), InputError);
  o = {};
  o.R_body_cam(0, 0) = 2.0;  // not a rotation
  std::string why;
  EXPECT_FALSE(o.isValid(&why));
  EXPECT_NE(why.find("R_body_cam"), std::string::npos) << why;
  EXPECT_THROW(StarTracker(test::simDatabase(), test::simCamera(), o), InputError);
}

}  // namespace
}  // namespace st
