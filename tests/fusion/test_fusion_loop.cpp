// FusionLoop (fusion/fusion_loop.hpp): the policies that replay, live and the Monte Carlo share,
// each on a small synthetic stream (still or rotating gyro, fixes as FrameResults).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/attitude.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "fusion/fusion_loop.hpp"

namespace st {
namespace {

FrameResult fixOf(const Quat& q, double sigma, StarTrackerMode mode = StarTrackerMode::kTracking) {
  FrameResult f;
  f.mode = mode;
  f.q_ib = q;
  f.cov_body = Mat3::Identity() * sigma * sigma;
  return f;
}

bool hasWarning(const FusionLoop& loop, const std::string& what) {
  const auto& w = loop.warnings();
  return std::any_of(w.begin(), w.end(),
                     [&](const std::string& m) { return m.find(what) != std::string::npos; });
}

const Quat kQ0 = attitudeFromRaDecRoll({0.5, 0.2, 0.1});

TEST(FusionLoop, ReinitialisesFromTheNextLostInSpaceFixAfterRejectionsInARow) {
  FusionOptions o;
  o.reorder_window_s = 0;
  FusionLoop loop(o);
  const Quat q1 = kQ0 * quatExp(Vec3(0, 0.01, 0));  // the sky jumps by 0.57 deg at t = 5 s
  const double sigma = arcsec2rad(5);
  std::vector<FixUse> uses;
  loop.setStepCallback([&](const FusionStep& s) { uses.push_back(s.use); });
  bool asked_lis = false;
  for (int k = 0; k <= 1000; ++k) {  // 10 s of a still gyro at 100 Hz, fixes at 5 Hz
    const double t = 0.01 * k;
    loop.pushGyro(t, Vec3::Zero());
    if (k % 20 != 0) continue;
    // What a tracker would do with the loop's inputs: lost-in-space when asked for.
    const bool lis = loop.frameInputs(t).force_lost_in_space;
    asked_lis = asked_lis || lis;
    loop.pushFix(t, k, fixOf(t < 5 ? kQ0 : q1, sigma,
                             lis ? StarTrackerMode::kLostInSpace : StarTrackerMode::kTracking));
  }
  loop.flush();
  EXPECT_TRUE(asked_lis);
  EXPECT_EQ(loop.reinitializations(), 1);
  auto count = [&](FixUse u) { return std::count(uses.begin(), uses.end(), u); };
  EXPECT_EQ(count(FixUse::kInitialized), 1);
  EXPECT_EQ(count(FixUse::kRejected), o.reinit_after_rejections);  // 5.0, 5.2, 5.4 s
  EXPECT_EQ(count(FixUse::kReinitialized), 1);                       // 5.6 s, lost-in-space
  EXPECT_EQ(count(FixUse::kAccepted), 24 + 22);
  EXPECT_LT(attitudeError(loop.filter().attitude(), q1).total, 3 * sigma);
  EXPECT_TRUE(hasWarning(loop, "in a row rejected"));
}

TEST(FusionLoop, TrackingFixesAreIgnoredWhileARestartWaitsForLostInSpace) {
  FusionOptions o;
  o.reorder_window_s = 0;
  FusionLoop loop(o);
  const Quat q1 = kQ0 * quatExp(Vec3(0.02, 0, 0));
  std::vector<FixUse> uses;
  loop.setStepCallback([&](const FusionStep& s) { uses.push_back(s.use); });
  double t = 0;
  loop.pushFix(t, 0, fixOf(kQ0, 1e-5));
  for (int k = 1; k <= 6; ++k) {  // a live tracker that keeps tracking on its own prediction
    t = 0.1 * k;
    loop.pushGyro(t, Vec3::Zero());
    loop.pushFix(t, k, fixOf(q1, 1e-5));
  }
  ASSERT_TRUE(loop.reinitPending());
  EXPECT_EQ(std::count(uses.begin(), uses.end(), FixUse::kIgnored), 3);  // after 3 rejected
  loop.pushGyro(0.7, Vec3::Zero());
  loop.pushFix(0.7, 7, fixOf(q1, 1e-5, StarTrackerMode::kLostInSpace));
  EXPECT_EQ(uses.back(), FixUse::kReinitialized);
  EXPECT_FALSE(loop.reinitPending());
  EXPECT_FALSE(loop.frameInputs(0.8).force_lost_in_space);
}

TEST(FusionLoop, SortsInsideTheWindowAndDropsDuplicatesAndLateEvents) {
  FusionOptions o;
  o.reorder_window_s = 0.05;
  FusionLoop loop(o);
  std::vector<double> times;
  loop.setStepCallback([&](const FusionStep& s) { times.push_back(s.t); });
  loop.pushFix(0.0, 0, fixOf(kQ0, 1e-4));
  loop.pushGyro(0.02, Vec3::Zero());
  loop.pushGyro(0.01, Vec3::Zero());  // swapped inside the window: sorted silently
  loop.pushMarker(0.03, 1);
  loop.pushMarker(0.03, 2);  // duplicate
  for (int k = 3; k <= 10; ++k) loop.pushGyro(0.01 * k, Vec3::Zero());
  loop.pushGyro(0.005, Vec3::Zero());  // beyond the window: out of order
  loop.flush();
  EXPECT_EQ(times, (std::vector<double>{0.0, 0.03}));
  EXPECT_TRUE(hasWarning(loop, "duplicate marker at t = 0.030000 s"));
  EXPECT_TRUE(hasWarning(loop, "out-of-order gyro sample at t = 0.005000 s"));
  EXPECT_EQ(loop.warningCount(), 2);
}

TEST(FusionLoop, NonFiniteGyroSamplesAreDroppedNotIntegrated) {
  FusionOptions o;
  o.reorder_window_s = 0;
  FusionLoop loop(o);
  loop.pushFix(0.0, 0, fixOf(kQ0, 1e-4));
  loop.pushGyro(0.01, Vec3(std::nan(""), 0, 0));
  loop.pushGyro(0.02, Vec3(0, std::numeric_limits<double>::infinity(), 0));
  loop.pushGyro(0.03, Vec3::Zero());
  EXPECT_TRUE(loop.filter().attitude().coeffs().allFinite());
  EXPECT_TRUE(loop.filter().covariance().allFinite());
  EXPECT_TRUE(hasWarning(loop, "non-finite rate"));
  EXPECT_EQ(loop.warningCount(), 2);
}

TEST(FusionLoop, InputsPropagateThroughGyroSamplesStillHeldForOrdering) {
  // A live tracker asks ahead of the filter, which lags by the reorder window: the
  // prediction must use the samples already received, not extrapolate the last processed one.
  FusionOptions o;
  o.reorder_window_s = 0.5;
  FusionLoop loop(o);
  loop.pushFix(0.0, 0, fixOf(kQ0, 1e-4));
  const Vec3 w(0, 0, deg2rad(2.0));  // still, then 2 deg/s about the boresight from 0.5 s
  for (int k = 1; k <= 100; ++k) loop.pushGyro(0.01 * k, k > 50 ? w : Vec3::Zero());
  ASSERT_NEAR(loop.filter().time(), 0.5, 1e-12);  // the samples after 0.5 s are held
  const FrameInputs in = loop.frameInputs(1.0);
  ASSERT_TRUE(in.prediction.has_value());
  const Quat truth = kQ0 * quatExp(w * 0.5);
  EXPECT_LT(attitudeError(in.prediction->q_ib, truth).total, arcsec2rad(1.0));
  EXPECT_LT((in.prediction->rate_body - w).norm(), 1e-9);
  // The filter's own prediction without those samples is 1 deg off.
  EXPECT_GT(attitudeError(loop.filter().predictAt(1.0).q_ib, truth).total, deg2rad(0.9));
}

TEST(FusionLoop, GyroMountingRotatesTheRatesIntoTheBody) {
  FusionOptions o;
  o.reorder_window_s = 0;
  o.R_body_gyro = quatExp(Vec3(0, 0, M_PI / 2)).toRotationMatrix();  // gyro x = body y
  FusionLoop loop(o);
  loop.pushFix(0.0, 0, fixOf(kQ0, 1e-4));
  for (int k = 1; k <= 10; ++k) loop.pushGyro(0.01 * k, Vec3(0.1, 0, 0));
  const FrameInputs in = loop.frameInputs(0.1);
  ASSERT_TRUE(in.prediction.has_value());
  EXPECT_LT((in.prediction->rate_body - Vec3(0, 0.1, 0)).norm(), 1e-9);
  EXPECT_LT(attitudeError(loop.filter().attitude(), kQ0 * quatExp(Vec3(0, 0.01, 0))).total, 1e-9);
}

TEST(FusionLoop, GyroGapIsCoastedWithTheHeldRateErrorAdded) {
  auto run = [](bool gap) {
    FusionOptions o;
    o.reorder_window_s = 0;
    FusionLoop loop(o);
    loop.pushFix(0.0, 0, fixOf(kQ0, 1e-5));
    for (int k = 1; k <= 300; ++k) {
      if (gap && k > 100 && k < 200) continue;  // 1 s without samples
      loop.pushGyro(0.01 * k, Vec3(0, 0, 0.01));
    }
    return loop;
  };
  const FusionLoop with_gap = run(true), without = run(false);
  EXPECT_TRUE(hasWarning(with_gap, "gyro gap of 1.000 s"));
  EXPECT_FALSE(hasWarning(without, "gyro gap"));
  // Both end at the same attitude (the held rate is the true one) ...
  EXPECT_LT(attitudeError(with_gap.filter().attitude(), without.filter().attitude()).total, 1e-9);
  // ... but the coasted filter is less certain.
  EXPECT_GT(with_gap.filter().attitudeCov().trace(), 1.5 * without.filter().attitudeCov().trace());
}

TEST(FusionLoop, BeforeAnAttitudeTheTrackerGetsTheGyroRate) {
  FusionOptions o;
  o.reorder_window_s = 0;
  FusionLoop loop(o);
  EXPECT_FALSE(loop.frameInputs(0.0).rate_body.has_value());
  for (int k = 1; k <= 20; ++k) loop.pushGyro(0.01 * k, Vec3(0.03, 0, 0));
  const FrameInputs in = loop.frameInputs(0.2);
  EXPECT_FALSE(in.prediction.has_value());
  ASSERT_TRUE(in.rate_body.has_value());
  EXPECT_LT((*in.rate_body - Vec3(0.03, 0, 0)).norm(), 1e-12);
  EXPECT_FALSE(loop.frameInputs(5.0).rate_body.has_value());  // stale after a long silence
}

TEST(FusionLoop, BadOptionsAreInputErrorsNamingTheOption) {
  FusionOptions o;
  o.reinit_after_rejections = 0;
  try {
    FusionLoop loop(o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("reinit_after_rejections"), std::string::npos);
  }
  o = FusionOptions{};
  o.R_body_gyro = 2 * Mat3::Identity();
  EXPECT_THROW(FusionLoop{o}, InputError);
}

}  // namespace
}  // namespace st
