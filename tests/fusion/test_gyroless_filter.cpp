// The gyroless mode of AttitudeMekf (fusion/gyroless_model.hpp) and of the fusion loop:
// closed-form transition against the nonlinear error propagation, process noise against its
// integral, the rate update, and the loop's gyroless policies (gyro samples not used, the
// prediction's rate handed to the tracker, re-initialisation from the fix's own rate).
#include <gtest/gtest.h>

#include <cmath>

#include "common/conventions.hpp"
#include "fusion/fusion_loop.hpp"
#include "fusion/gyroless_model.hpp"
#include "fusion/mekf.hpp"

namespace st {
namespace {

MekfOptions gyroless(double walk = 1e-3) {
  MekfOptions o;
  o.model = MekfOptions::Model::kGyroless;
  o.rate_walk_rad_s2_rt_hz = walk;
  o.initial_rate_sigma_rad_s = deg2rad(1.0);
  return o;
}

// Error propagation: the truth (q Exp(d0), w + dw) and the estimate (q, w) both move at their
// own constant rates; the error after dt is Phi [d0; dw] to first order.
TEST(GyrolessModel, TransitionIsTheLinearisedErrorPropagation) {
  const Vec3 w(0.3, -0.5, 0.8);  // large: |w| dt = 0.5 rad, away from the series branch
  const double dt = 0.5;
  const Vec3 d0(2e-6, -1e-6, 3e-6), dw(1e-6, 2e-6, -1.5e-6);
  const Quat q = attitudeFromRaDecRoll({0.4, 0.2, 0.1});
  const Quat q_true = q * quatExp(d0) * quatExp((w + dw) * dt);
  const Quat q_est = q * quatExp(w * dt);
  const Vec3 d1 = quatLog(canonical(q_est.conjugate() * q_true));
  Vec6 x0;
  x0 << d0, dw;
  const Vec6 x1 = gyrolessTransition(w, dt) * x0;
  EXPECT_LT((x1.head<3>() - d1).norm(), 1e-3 * d1.norm());
  EXPECT_LT((x1.tail<3>() - dw).norm(), 1e-15);
  // The small-angle series matches the closed form where they meet.
  const Vec3 ws = w.normalized() * (0.99e-4 / dt), wl = w.normalized() * (1.01e-4 / dt);
  EXPECT_LT((gyrolessTransition(ws, dt) - gyrolessTransition(wl, dt)).norm(), 1e-5);
}

// Q = int_0^dt Phi(s) G sw^2 G^T Phi(s)^T ds, evaluated by the midpoint rule at zero rate.
TEST(GyrolessModel, ProcessNoiseIsTheIntegralOfTheRateWalk) {
  const double sw = 2e-4, dt = 0.3;
  Mat6 Qn = Mat6::Zero();
  constexpr int kN = 3000;
  Eigen::Matrix<double, 6, 3> G = Eigen::Matrix<double, 6, 3>::Zero();
  G.bottomRows<3>().setIdentity();
  for (int k = 0; k < kN; ++k) {
    const double s = (k + 0.5) * dt / kN;
    const Mat6 Phi = gyrolessTransition(Vec3::Zero(), s);
    Qn += Phi * G * (sw * sw) * G.transpose() * Phi.transpose() * (dt / kN);
  }
  EXPECT_LT((gyrolessProcessNoise(sw, dt) - Qn).norm(), 1e-6 * Qn.norm());
}

TEST(GyrolessFilter, PropagatesAtItsOwnRateAndTakesRateUpdates) {
  AttitudeMekf f(gyroless());
  const Quat q0 = attitudeFromRaDecRoll({1.0, 0.3, 0.2});
  const Vec3 w(deg2rad(0.5), 0, deg2rad(-0.2));
  Mat6 P = Mat6::Zero();
  P.topLeftCorner<3, 3>() = Mat3::Identity() * 1e-10;
  P.bottomRightCorner<3, 3>() = Mat3::Identity() * 1e-6;
  f.initialize(0, q0, w, P);
  EXPECT_TRUE(f.gyroless());
  EXPECT_EQ(f.rate(), w);
  const MekfPrediction p = f.predictAt(2.0);
  EXPECT_LT(quatLog(canonical(p.q_ib.conjugate() * q0 * quatExp(w * 2.0))).norm(), 1e-12);
  EXPECT_EQ(p.rate, w);
  EXPECT_EQ(f.time(), 0.0);  // predictAt leaves the filter alone
  // The rate's uncertainty grows the attitude's: 1e-6 rad^2/s^2 over 2 s -> 4e-6 rad^2.
  EXPECT_NEAR(p.P(0, 0), 1e-10 + 4e-6 + 1e-6 * 8.0 / 3.0, 1e-9);
  ASSERT_TRUE(f.predictTo(2.0));
  EXPECT_EQ(f.time(), 2.0);
  // A rate measurement 0.01 deg/s off with a 0.001 rad/s sigma: pulled about halfway.
  const Vec3 meas = w + Vec3(deg2rad(0.01), 0, 0);
  const double before = f.covariance()(3, 3);
  const MekfUpdateResult u = f.updateRate(meas, Mat3::Identity() * before);
  ASSERT_TRUE(u.accepted) << u.reason;
  EXPECT_EQ(u.dof, 3);
  EXPECT_NEAR(f.rate().x(), w.x() + 0.5 * deg2rad(0.01), 1e-3 * deg2rad(0.01));
  EXPECT_NEAR(f.covariance()(3, 3), 0.5 * before, 1e-6 * before);
  // The gyro model has no rate state: refused, filter unchanged.
  AttitudeMekf g(MekfOptions::fromDatasheet(0.15, 0.5, 10));
  g.initialize(0, q0, Mat3::Identity() * 1e-8);
  const MekfUpdateResult ug = g.updateRate(meas, Mat3::Identity());
  EXPECT_FALSE(ug.accepted);
  EXPECT_NE(ug.reason.find("no rate"), std::string::npos);
}

FrameResult fix(const Quat& q, StarTrackerMode mode = StarTrackerMode::kTracking) {
  FrameResult f;
  f.mode = mode;
  f.q_ib = q;
  f.cov_body = Mat3::Identity() * std::pow(arcsec2rad(5), 2);
  return f;
}

TEST(GyrolessLoop, IgnoresGyroSamplesAndHandsItsRateToTheTracker) {
  FusionOptions o;
  o.filter = gyroless();
  o.reorder_window_s = 0;
  FusionLoop loop(o);
  const Quat q0 = attitudeFromRaDecRoll({0.5, -0.1, 0.3});
  const Vec3 w(deg2rad(0.8), deg2rad(-0.3), deg2rad(0.1));
  std::vector<FixUse> uses;
  loop.setStepCallback([&](const FusionStep& s) { uses.push_back(s.use); });
  for (int k = 0; k < 10; ++k) loop.pushGyro(0.01 * k, Vec3(1, 2, 3));  // not used
  EXPECT_EQ(loop.warningCount(), 1);
  EXPECT_NE(loop.warnings()[0].find("not used: the filter model is gyroless"), std::string::npos);
  // No attitude yet: no prediction and no rate (the gyro samples were not taken).
  const FrameInputs in0 = loop.frameInputs(0.1);
  EXPECT_FALSE(in0.prediction);
  EXPECT_FALSE(in0.rate_body);
  loop.pushFix(0.1, 1, fix(q0, StarTrackerMode::kLostInSpace));
  // The second frame already has a prediction (zero rate, the prior's covariance).
  const FrameInputs in1 = loop.frameInputs(0.3);
  ASSERT_TRUE(in1.prediction);
  EXPECT_GT(in1.prediction->cov_body(0, 0), std::pow(deg2rad(1.0) * 0.2, 2) * 0.99);
  for (int k = 1; k <= 20; ++k) loop.pushFix(0.1 + 0.2 * k, 1 + k, fix(q0 * quatExp(w * 0.2 * k)));
  loop.flush();
  ASSERT_EQ(uses.size(), 21u);
  EXPECT_EQ(uses[0], FixUse::kInitialized);
  for (std::size_t k = 1; k < uses.size(); ++k) EXPECT_EQ(uses[k], FixUse::kAccepted) << k;
  const FrameInputs in = loop.frameInputs(4.3);
  ASSERT_TRUE(in.prediction);
  EXPECT_LT((in.prediction->rate_body - w).norm(), deg2rad(1e-3));
  EXPECT_LT(quatLog(canonical(in.prediction->q_ib.conjugate() * q0 * quatExp(w * 4.2))).norm(),
            arcsec2rad(1));
}

// Fixes that jump away (the body turned while the filter held its rate) are refused until
// the loop asks for lost-in-space; the re-initialisation restarts attitude AND rate, the rate
// from the lost-in-space fix's own frame-to-frame rate.
TEST(GyrolessLoop, ReinitialisationRestartsTheRateFromTheFixesOwnRate) {
  FusionOptions o;
  o.filter = gyroless();
  o.reorder_window_s = 0;
  FusionLoop loop(o);
  std::vector<FusionStep> steps;
  loop.setStepCallback([&](const FusionStep& s) { steps.push_back(s); });
  const Quat q0 = attitudeFromRaDecRoll({0.5, -0.1, 0.3});
  for (int k = 0; k < 5; ++k) loop.pushFix(0.2 * k, k, fix(q0));
  const Quat away = q0 * quatExp(Vec3(0.05, 0, 0));
  int k = 5;
  while (!loop.frameInputs(0.2 * k).force_lost_in_space && k < 20) {
    loop.pushFix(0.2 * k, k, fix(away));
    ++k;
  }
  ASSERT_LT(k, 20);
  FrameResult lis = fix(away, StarTrackerMode::kLostInSpace);
  MeasuredRate r;
  r.rate_body = Vec3(0.01, 0.02, -0.01);
  r.cov_body = Mat3::Identity() * 1e-8;
  r.interval_s = 0.2;
  r.stars = 10;
  lis.rate = r;
  loop.pushFix(0.2 * k, k, lis);
  loop.flush();
  ASSERT_EQ(steps.back().use, FixUse::kReinitialized);
  EXPECT_EQ(loop.reinitializations(), 1);
  EXPECT_TRUE(steps.back().filter.gyroless);
  EXPECT_EQ(steps.back().filter.rate, r.rate_body);
  EXPECT_EQ(Mat3(steps.back().filter.P.bottomRightCorner<3, 3>()), r.cov_body);
}

}  // namespace
}  // namespace st
