// The tracker's camera model (issue 19): a camera file that is a few percent off and ignores
// the lens's distortion is healed by lost-in-space and refined online from the verified
// frames, with a camera-model error term in the fixes' covariances; an exact camera keeps
// today's covariances (no model error appears). And re-acquisition: an unrelated frame after
// frame-to-frame tracking goes to lost-in-space at once.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "common/conventions.hpp"
#include "sensors/sim/motion.hpp"
#include "sensors/tracking/star_tracker.hpp"
#include "tests/tracking/tracker_scoring.hpp"
#include "tests/tracking/tracker_sim.hpp"

namespace st {
namespace {

using test::FrameSimulator;
using namespace test::scoring;

/// The true lens: the simulation camera with the radial distortion of a real star-tracker
/// lens (k1 = 0.1 moves the corner stars of this 16 x 12 deg field by ~1.5 px; the real
/// frames' 11 deg lens fits k1 = 0.098, README "calibrate").
CameraModel trueLens() {
  const CameraModel& c = test::simCamera();
  Distortion d;
  d.k1 = 0.1;
  return CameraModel(c.width(), c.height(), c.fx(), c.fy(), c.cx(), c.cy(), d);
}

/// A camera file as a datasheet gives it: focal length `rel` off, no distortion.
CameraModel datasheetCamera(double rel) {
  const CameraModel& c = test::simCamera();
  return CameraModel(c.width(), c.height(), c.fx() * (1 + rel), c.fy() * (1 + rel), c.cx(),
                     c.cy());
}

struct CameraRun {
  RunStats stats;
  int solved = 0, frames = 0, camera_updates = 0;
  double last_model_error_px = 0;
  std::vector<double> error2;  ///< [rad^2] squared attitude error of each fix

  /// Mean NEES and RMS error [arcsec] of the fixes from the `from`-th on.
  double meanNeesFrom(std::size_t from) const {
    double sum = 0;
    for (std::size_t k = from; k < stats.nees.size(); ++k) sum += stats.nees[k];
    return sum / double(stats.nees.size() - from);
  }
  double rmsArcsecFrom(std::size_t from) const {
    double sum = 0;
    for (std::size_t k = from; k < error2.size(); ++k) sum += error2[k];
    return rad2arcsec(std::sqrt(sum / double(error2.size() - from)));
  }
};


/// A slow slew (rate match tracking) of `n` frames at 10 Hz through `file` while the frames
/// are rendered through `truth`.
CameraRun run(StarTracker& tracker, const CameraModel& truth, int n, uint64_t seed) {
  const SlewMotion motion(startAttitude(), Vec3(deg2rad(0.2), deg2rad(-0.1), 0.0));
  FrameSimulator sim(seed, truth);
  CameraRun r;
  for (int k = 0; k < n; ++k) {
    const auto f = sim.frame(motion, 0.1 * k);
    const FrameResult o = tracker.process(f.image, f.t_s);
    ++r.frames;
    r.solved += o.hasAttitude();
    r.camera_updates += o.camera_updated;
    r.last_model_error_px = o.model_error_px;
    score(o, f, f.q_ib, r.stats);
    if (o.hasAttitude()) r.error2.push_back(std::pow(attitudeError(o.q_ib, f.q_ib).total, 2));
  }
  return r;
}

/// The same frames through a tracker that is given the true lens and learns nothing: what
/// the tracker does with a perfect calibration (the yardstick of the runs above).
CameraRun referenceRun(const CameraModel& truth, int n, uint64_t seed) {
  TrackerOptions o = test::simTrackerOptions();
  o.camera_heal_range = 0;
  o.online_camera.enabled = false;
  StarTracker tracker(test::simDatabase(), truth, o);
  return run(tracker, truth, n, seed);
}

TEST(TrackerCamera, AFileTwoPercentOffWithoutDistortionIsHealedAndRefinedOnline) {
  const CameraModel truth = trueLens();
  StarTracker tracker(test::simDatabase(), datasheetCamera(0.02), test::simTrackerOptions());
  const CameraRun r = run(tracker, truth, 80, 1901);
  EXPECT_EQ(r.solved, r.frames);
  expectRightStars(r.stats);
  // The first frame heals the file; the online fits refine it: after 10, 30 and 70 verified
  // frames (the interval doubles while a fit finds no model error, online_camera.hpp).
  EXPECT_GE(r.camera_updates, 1 + 3);
  ASSERT_TRUE(tracker.cameraFit().has_value());
  const CameraFitResult& fit = *tracker.cameraFit();
  // The refined camera against the truth, within 4 sigma of its own uncertainty (the online
  // posterior's), and far closer than the file.
  const double dfx = tracker.camera().fx() - truth.fx();
  EXPECT_LT(std::abs(dfx), 4 * fit.sigma(kFx) + 1e-9) << "fx " << tracker.camera().fx()
                                                      << " +- " << fit.sigma(kFx);
  EXPECT_LT(std::abs(dfx) / truth.fx(), 2e-4);
  EXPECT_NEAR(tracker.camera().distortion().k1, truth.distortion().k1,
              4 * fit.sigma(kK1) + 1e-9);
  // After the camera settled (from the second online fit on), the fixes are as good and as
  // consistent as with a perfect calibration on the same frames. (The yardstick, not a
  // chi-square band: this slow slew's tracking fixes are ~3x optimistic with the perfect
  // camera too -- mean NEES ~9 -- a common-mode centroid error of ~0.3" that no residual
  // shows; noted in issue 19.)
  const CameraRun ref = referenceRun(truth, 80, 1901);
  std::printf("[ info ] file 2 %% off: fx %.2f (truth %.2f) +- %.2f, k1 %.4f +- %.4f; settled "
              "RMS %.2f\" vs %.2f\" with the true lens, mean NEES %.2f vs %.2f\n",
              tracker.camera().fx(), truth.fx(), fit.sigma(kFx), tracker.camera().distortion().k1,
              fit.sigma(kK1), r.rmsArcsecFrom(20), ref.rmsArcsecFrom(20), r.meanNeesFrom(20),
              ref.meanNeesFrom(20));
  EXPECT_LT(r.rmsArcsecFrom(20), 1.2 * ref.rmsArcsecFrom(20));
  EXPECT_LT(r.meanNeesFrom(20), 1.3 * ref.meanNeesFrom(20));
}

TEST(TrackerCamera, WithoutHealingTheSameFileSolvesNothing) {
  // Teeth: the healing, not a lenient gate, is what solves the frames above.
  TrackerOptions o = test::simTrackerOptions();
  o.camera_heal_range = 0;
  o.online_camera.enabled = false;
  StarTracker tracker(test::simDatabase(), datasheetCamera(0.02), o);
  const CameraRun r = run(tracker, trueLens(), 5, 1901);
  EXPECT_EQ(r.solved, 0);
}

TEST(TrackerCamera, AnExactCameraStaysExactAndItsFixesKeepTheirCovariance) {
  // Simulated runs keep today's accuracy and NEES: with the true camera the residuals show
  // no model error (the term stays 0) and the online fits move the focal length by noise.
  StarTracker tracker(test::simDatabase(), test::simCamera(), test::simTrackerOptions());
  const CameraRun r = run(tracker, test::simCamera(), 80, 1902);
  EXPECT_EQ(r.solved, r.frames);
  expectRightStars(r.stats);
  EXPECT_EQ(tracker.modelErrorPx(), 0.0);
  EXPECT_LT(std::abs(tracker.camera().fx() / test::simCamera().fx() - 1), 1e-4);
  const CameraRun ref = referenceRun(test::simCamera(), 80, 1902);
  std::printf("[ info ] exact camera: RMS %.3f\" vs %.3f\" without online refinement, mean "
              "NEES %.2f vs %.2f\n",
              r.rmsArcsecFrom(0), ref.rmsArcsecFrom(0), r.meanNeesFrom(0), ref.meanNeesFrom(0));
  EXPECT_LT(std::abs(r.rmsArcsecFrom(0) / ref.rmsArcsecFrom(0) - 1), 0.1);
  EXPECT_LT(std::abs(r.meanNeesFrom(0) / ref.meanNeesFrom(0) - 1), 0.15);
}

TEST(TrackerCamera, AnUnrelatedFrameGoesToLostInSpaceAtOnceWithoutAnIndependentRate) {
  // Frame-to-frame tracking (no gyro, no filter) of one field, then frames of a field 60 deg
  // away: the windows find nothing, and nothing independent of our own fixes says where the
  // stars are, so the same frame is solved lost-in-space.
  const HoldMotion here(startAttitude());
  const HoldMotion there(attitudeFromRaDecRoll({deg2rad(144.0), deg2rad(10.0), deg2rad(-40.0)}));
  FrameSimulator sim(1903);
  StarTracker tracker(test::simDatabase(), test::simCamera(), test::simTrackerOptions());
  for (int k = 0; k < 8; ++k) {
    const bool moved = k >= 5;
    const auto f = sim.frame(moved ? static_cast<const MotionProfile&>(there) : here, 0.1 * k);
    const FrameResult o = tracker.process(f.image, f.t_s);
    ASSERT_TRUE(o.hasAttitude()) << "frame " << k << ": " << o.detail;
    EXPECT_LT(rad2arcsec(attitudeError(o.q_ib, f.q_ib).total), 60.0) << "frame " << k;
    if (k == 5) {
      EXPECT_EQ(o.mode, StarTrackerMode::kLostInSpace) << o.detail;
      EXPECT_TRUE(o.fell_back_to_lost_in_space);
      EXPECT_TRUE(reacquiredInFrame(o.mode, o.detail)) << o.detail;
    }
    if (k >= 2 && k != 5 && k != 6) {
      EXPECT_EQ(o.mode, StarTrackerMode::kTracking) << "frame " << k;
    }
  }
}

}  // namespace
}  // namespace st
