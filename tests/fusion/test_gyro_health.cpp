// Gyro health checks (fusion/gyro_health.hpp) and what the fusion loop does with them: each
// check on a synthetic 100 Hz gyro with the datasheet's white noise, and the false-alarm rate
// of all of them on a long healthy stream.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "common/attitude.hpp"
#include "common/conventions.hpp"
#include "fusion/fusion_loop.hpp"
#include "fusion/gyro_health.hpp"

namespace st {
namespace {

constexpr double kDt = 0.01;  // 100 Hz
// The filter's default datasheet (FusionOptions): ARW 0.15 deg/sqrt(h) -> per sample
// sigma_s = sigma_v / sqrt(dt) = 0.025 deg/s.
const double kSigmaS = MekfOptions::fromDatasheet(0.15, 0.5, 10.0).arw_rad_rt_s / std::sqrt(kDt);

/// A gyro on a body turning at `rate` plus a slow sinusoid (0.7 deg/s^2 peak acceleration,
/// the fault scenarios' jitter), with white noise of sigma_s.
struct Gyro {
  std::mt19937_64 rng{42};
  std::normal_distribution<double> n{0.0, 1.0};
  Vec3 rate = Vec3(deg2rad(0.5), deg2rad(1.0), deg2rad(0.2));
  Vec3 truth(double t) const {
    return rate + Vec3(std::sin(0.7 * t), std::cos(0.45 * t), std::sin(0.8 * t)) * deg2rad(1.0);
  }
  Vec3 sample(double t) { return truth(t) + Vec3(n(rng), n(rng), n(rng)) * kSigmaS; }
};

TEST(GyroHealth, HealthyGyroRaisesNoAlarmInAnHourOfSamples) {
  // 360000 samples, 3 axes: every check's false-alarm probability (header: ~1e-7 and below
  // per window) makes one alarm here unlikely (< 0.1); a spike flag at 10 sigma, none.
  GyroHealth h;
  Gyro g;
  int unhealthy = 0;
  for (int k = 0; k < 360000; ++k) {
    const GyroSampleCheck c = h.check(g.sample(k * kDt), kDt, kSigmaS);
    unhealthy += !c.healthy;
  }
  EXPECT_EQ(h.spikes(), 0);
  EXPECT_EQ(unhealthy, 0);
}

TEST(GyroHealth, SpikeIsReplacedByTheMedianOfTheSamplesBefore) {
  GyroHealth h;
  Gyro g;
  for (int k = 0; k < 100; ++k) h.check(g.sample(k * kDt), kDt, kSigmaS);
  Vec3 spiked = g.sample(1.0);
  spiked.y() += deg2rad(5.0);  // fault_gyro_spikes.ini's size
  const GyroSampleCheck c = h.check(spiked, kDt, kSigmaS);
  EXPECT_TRUE(c.spike);
  EXPECT_TRUE(c.healthy);  // one spike is not a faulty axis
  // The replacement is within the median's noise and a sample's ramp of the truth.
  EXPECT_LT(std::abs(c.rate.y() - g.truth(1.0).y()), 5 * kSigmaS);
  EXPECT_EQ(c.rate.x(), spiked.x());  // the other axes untouched
}

TEST(GyroHealth, RateStepIsAcceptedAfterThreeAgreeingSamplesWithTheAngleItCost) {
  GyroHealth h;
  Gyro g;
  for (int k = 0; k < 100; ++k) h.check(g.sample(k * kDt), kDt, kSigmaS);
  const double step = deg2rad(2.0);  // a thruster: 2 deg/s at once on z
  Vec3 err = Vec3::Zero();
  bool spike_seen = false;
  for (int k = 100; k < 110; ++k) {
    Vec3 s = g.sample(k * kDt);
    s.z() += step;
    const GyroSampleCheck c = h.check(s, kDt, kSigmaS);
    spike_seen = spike_seen || c.spike;
    err += c.step_error;
    EXPECT_TRUE(c.healthy) << k;
    if (k >= 102) {
      EXPECT_NEAR(c.rate.z(), s.z(), 1e-12) << k;  // the new level is used
    }
  }
  EXPECT_TRUE(spike_seen);
  // The two samples replaced before the step was recognised: 2 x step x dt.
  EXPECT_NEAR(err.z(), 2 * step * kDt, 4 * kSigmaS * kDt);
}

TEST(GyroHealth, StuckAxisIsFoundWithinHalfAWindowAndClearsAfterAFullOne) {
  GyroHealth h;
  Gyro g;
  for (int k = 0; k < 100; ++k) h.check(g.sample(k * kDt), kDt, kSigmaS);
  const double held = g.sample(1.0).y();
  int found_after = -1, cleared_after = -1;
  for (int k = 0; k < 200; ++k) {
    Vec3 s = g.sample(1.0 + k * kDt);
    if (k < 100) s.y() = held;  // stuck for 1 s
    const GyroSampleCheck c = h.check(s, kDt, kSigmaS);
    if (c.changed && !c.healthy) {
      found_after = k;
      EXPECT_NE(c.why.find("axis y stuck"), std::string::npos) << c.why;
    }
    if (c.changed && c.healthy) cleared_after = k - 100;
  }
  EXPECT_GE(found_after, 8);   // 10 repeats of 20 (the first stuck sample repeats nothing...
  EXPECT_LE(found_after, 10);  // ...when the noise moved it): samples 9 or 10
  EXPECT_GT(cleared_after, 0);
  EXPECT_LE(cleared_after, 10 + 20);  // repeats fall below half, then 20 clean samples
}

TEST(GyroHealth, AllAxesRepeatingIsAStillNoiseFreeGyroNotAStuckAxis) {
  GyroHealth h;
  for (int k = 0; k < 500; ++k)
    EXPECT_TRUE(h.check(Vec3(0.01, 0, -0.02), kDt, kSigmaS).healthy) << k;
}

TEST(GyroHealth, NoisyAxisIsFoundBothFarAboveAndModeratelyAboveTheDatasheet) {
  for (const double sigma_deg_s : {2.0, 0.2}) {  // 80x: spikes; 8x: below the spike bound
    SCOPED_TRACE(sigma_deg_s);
    GyroHealth h;
    Gyro g;
    std::normal_distribution<double> n(0.0, deg2rad(sigma_deg_s));
    std::mt19937_64 rng(7);
    for (int k = 0; k < 100; ++k) h.check(g.sample(k * kDt), kDt, kSigmaS);
    int found_after = -1;
    for (int k = 0; k < 100 && found_after < 0; ++k) {
      Vec3 s = g.sample(1.0 + k * kDt);
      s.x() += n(rng);
      const GyroSampleCheck c = h.check(s, kDt, kSigmaS);
      if (c.changed && !c.healthy) {
        found_after = k;
        EXPECT_NE(c.why.find("axis x noisy"), std::string::npos) << c.why;
      }
    }
    EXPECT_GE(found_after, 0);
    EXPECT_LE(found_after, 20);  // within a window
  }
}

// ---- the loop ---------------------------------------------------------------------------

FrameResult fixOf(const Quat& q, double sigma, StarTrackerMode mode) {
  FrameResult f;
  f.mode = mode;
  f.q_ib = q;
  f.cov_body = Mat3::Identity() * sigma * sigma;
  return f;
}

TEST(FusionLoopGyroHealth, SpikeDoesNotTurnTheFilter) {
  // A still body; a 5 deg/s spike for one 10 ms sample would turn the filter by 180" while
  // its attitude sigma is a few arcsec.
  FusionOptions o;
  o.reorder_window_s = 0;
  FusionLoop loop(o);
  Gyro g;
  g.rate = Vec3::Zero();
  const Quat q0 = attitudeFromRaDecRoll({0.5, 0.2, 0.1});
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n(0.0, kSigmaS);
  loop.pushFix(0, 0, fixOf(q0, arcsec2rad(5), StarTrackerMode::kLostInSpace));
  for (int k = 1; k <= 100; ++k) {
    Vec3 w(n(rng), n(rng), n(rng));
    if (k == 50) w.x() += deg2rad(5.0);
    loop.pushGyro(k * kDt, w);
  }
  loop.flush();
  EXPECT_EQ(loop.gyroSpikes(), 1);
  EXPECT_TRUE(loop.gyroHealthy());
  // Within 5 sigma of the filter's own covariance (the fix's 5" and 1 s of the ARW, 9" per
  // axis: 89" on the total); the spike alone would be 180".
  const double sigma_total = std::sqrt(loop.filter().attitudeCov().trace());
  EXPECT_LT(attitudeError(loop.filter().attitude(), q0).total, 5 * sigma_total);
}

TEST(FusionLoopGyroHealth, StuckAxisSuspendsTheFilterThenALostInSpaceFixRestartsIt) {
  FusionOptions o;
  o.reorder_window_s = 0;
  FusionLoop loop(o);
  const Quat q0 = attitudeFromRaDecRoll({0.5, 0.2, 0.1});
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n(0.0, kSigmaS);
  std::vector<FusionStep> steps;
  loop.setStepCallback([&](const FusionStep& s) { steps.push_back(s); });
  double held = 0;
  for (int k = 0; k <= 300; ++k) {  // 3 s; y stuck from 1 s to 2 s; fixes at 10 Hz
    const double t = k * kDt;
    Vec3 w(n(rng), n(rng), n(rng));
    if (t < 1.0) held = w.y();
    if (t >= 1.0 && t < 2.0) w.y() = held;
    loop.pushGyro(t, w);
    if (k % 10 != 0) continue;
    const bool lis = loop.frameInputs(t).force_lost_in_space;
    loop.pushFix(t, k, fixOf(q0, arcsec2rad(5),
                             lis ? StarTrackerMode::kLostInSpace : StarTrackerMode::kTracking));
  }
  loop.flush();
  double suspended_from = -1, restarted_at = -1;
  for (const FusionStep& s : steps) {
    if (suspended_from < 0 && s.use == FixUse::kUnfiltered) suspended_from = s.t;
    if (s.use == FixUse::kUnfiltered) {
      EXPECT_FALSE(s.filter.initialized) << s.t;
    }
    if (s.use == FixUse::kReinitialized) restarted_at = s.t;
  }
  EXPECT_NEAR(suspended_from, 1.1, 1e-9);  // found at 1.09 s, the next frame unfiltered
  EXPECT_GT(restarted_at, 2.0);
  EXPECT_LE(restarted_at, 2.0 + 0.1 + 0.2 + 0.1 + 1e-9);  // clear, 20 clean, next frame
  EXPECT_TRUE(loop.gyroHealthy());
  EXPECT_EQ(loop.reinitializations(), 1);
}

TEST(FusionLoopCameraClock, FrameStampedAheadOfTheGyroIsRefusedAndTheTimelineGoesOn) {
  FusionOptions o;
  o.reorder_window_s = 0.05;
  FusionLoop loop(o);
  const Quat q0 = attitudeFromRaDecRoll({0.5, 0.2, 0.1});
  std::vector<FusionStep> steps;
  std::vector<std::string> details;  // FusionStep::frame is valid during the callback only
  loop.setStepCallback([&](const FusionStep& s) {
    steps.push_back(s);
    details.push_back(s.frame ? s.frame->detail : "");
  });
  for (int k = 0; k <= 300; ++k) {  // frames stamped 1 s late from 1 s to 2 s
    const double t = k * kDt;
    loop.pushGyro(t, Vec3::Zero());
    if (k % 10 != 0) continue;
    const double stamp = t >= 1.0 && t < 2.0 ? t + 1.0 : t;
    loop.pushFix(stamp, k, fixOf(q0, arcsec2rad(5), StarTrackerMode::kTracking));
  }
  loop.flush();
  int refused = 0, used_after = 0, gyro_warnings = 0;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const FusionStep& s = steps[i];
    if (s.use == FixUse::kClockRefused) {
      ++refused;
      EXPECT_FALSE(s.filter.initialized);
      EXPECT_NE(details[i].find("camera clock 1.000 s ahead"), std::string::npos) << details[i];
    }
    if (s.t >= 2.0 && s.use == FixUse::kAccepted) ++used_after;
  }
  for (const std::string& w : loop.warnings()) gyro_warnings += w.find("gyro") == 0;
  EXPECT_EQ(refused, 10);
  EXPECT_EQ(loop.clockRefusedFrames(), 10);
  EXPECT_EQ(used_after, 11);  // 2.0 .. 3.0 s: the genuine frames at the refused ones' stamps
  EXPECT_EQ(gyro_warnings, 0);  // no gyro sample dropped as out of order
}

}  // namespace
}  // namespace st
