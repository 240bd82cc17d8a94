// Motion profiles: the truth every later test is measured against. Each profile's attitude
// must be the integral of its body rate (seed 002 eq. 10), checked with an independent
// integrator at a different step; closed forms checked analytically; tumbling conserves
// energy and the inertial angular momentum (this also pins the frame of the rate).
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <memory>

#include "common/attitude.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "sensors/sim/motion.hpp"

namespace st {
namespace {

const Quat kQ0 = attitudeFromRaDecRoll({deg2rad(40.0), deg2rad(-25.0), deg2rad(10.0)});

// Independent check: RK4 on q_dot = 1/2 q (x) (0, w(t)) using only rateBody(t), at a step
// unrelated to the profile's own grid.
Quat integrateRate(const MotionProfile& m, double t_end, double h) {
  Quat q = m.attitude(0);
  auto f = [&](double t, const Eigen::Vector4d& s) {
    const Quat qq(s[0], s[1], s[2], s[3]);
    const Quat d = qq * Quat(0, m.rateBody(t).x(), m.rateBody(t).y(), m.rateBody(t).z());
    return Eigen::Vector4d(0.5 * d.w(), 0.5 * d.x(), 0.5 * d.y(), 0.5 * d.z());
  };
  Eigen::Vector4d s(q.w(), q.x(), q.y(), q.z());
  const int n = static_cast<int>(std::ceil(t_end / h));
  const double dt = t_end / n;
  for (int i = 0; i < n; ++i) {
    const double t = i * dt;
    const Eigen::Vector4d k1 = f(t, s), k2 = f(t + dt / 2, s + dt / 2 * k1),
                          k3 = f(t + dt / 2, s + dt / 2 * k2), k4 = f(t + dt, s + dt * k3);
    s += dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    s.normalize();
  }
  return Quat(s[0], s[1], s[2], s[3]);
}

std::vector<std::unique_ptr<MotionProfile>> allProfiles() {
  std::vector<std::unique_ptr<MotionProfile>> v;
  v.push_back(std::make_unique<HoldMotion>(kQ0));
  v.push_back(std::make_unique<SlewMotion>(kQ0, Vec3(0.01, -0.02, 0.035)));
  v.push_back(
      std::make_unique<SlewAccelMotion>(kQ0, Vec3(1, 2, -1), deg2rad(3.0), deg2rad(1.0), 2.0, 1.0));
  v.push_back(std::make_unique<JitterMotion>(kQ0, Vec3(0.01, 0, -0.005), Vec3(0.002, 0.003, 0.001),
                                             Vec3(1.3, 4.0, 7.5), Vec3(0.1, 0.2, 0.3)));
  v.push_back(std::make_unique<TumbleMotion>(kQ0, Vec3(0.05, 0.3, 0.02), Vec3(1, 2, 3)));
  return v;
}

TEST(Motion, AttitudeIsTheIntegralOfTheBodyRate) {
  for (const auto& m : allProfiles()) {
    for (double t : {0.37, 3.0, 9.99}) {
      const Quat q_int = integrateRate(*m, t, 2.5e-4);
      const double err = attitudeError(m->attitude(t), q_int).total;
      EXPECT_LT(err, 1e-10) << m->type() << " t=" << t;
    }
  }
}

TEST(Motion, AttitudeDerivativeMatchesRateEverywhere) {
  // Central difference: Log(q(t-d)^-1 q(t+d)) / 2d = w(t) + O(d^2).
  const double d = 1e-4;
  for (const auto& m : allProfiles()) {
    for (double t = 0.05; t < 12; t += 0.731) {
      const Vec3 num = quatLog(m->attitude(t - d).conjugate() * m->attitude(t + d)) / (2 * d);
      EXPECT_LT((num - m->rateBody(t)).norm(), 1e-8) << m->type() << " t=" << t;
    }
  }
}

TEST(Motion, ClosedFormsHoldAndSlew) {
  const HoldMotion hold(kQ0);
  EXPECT_LT(attitudeError(hold.attitude(123.4), kQ0).total, 1e-15);
  EXPECT_EQ(hold.rateBody(5).norm(), 0.0);
  const Vec3 w(0, 0, deg2rad(2.0));
  const SlewMotion slew(kQ0, w);
  // 45 s at 2 deg/s about the boresight: roll advances by exactly 90 deg.
  const RaDecRoll a = raDecRollFromAttitude(slew.attitude(0));
  const RaDecRoll b = raDecRollFromAttitude(slew.attitude(45));
  EXPECT_NEAR(b.ra, a.ra, 1e-12);
  EXPECT_NEAR(b.dec, a.dec, 1e-12);
  EXPECT_NEAR(b.roll - a.roll, deg2rad(90.0), 1e-12);
}

TEST(Motion, SlewAccelTrapezoid) {
  const double max_rate = deg2rad(2.0), accel = deg2rad(0.5), coast = 10, start = 3;
  const SlewAccelMotion m(kQ0, Vec3(0, 1, 0), max_rate, accel, coast, start);
  const double ramp = max_rate / accel;  // 4 s
  EXPECT_DOUBLE_EQ(m.endTime(), start + 2 * ramp + coast);
  EXPECT_EQ(m.rateMagnitude(2.9), 0.0);
  EXPECT_NEAR(m.rateMagnitude(start + 1), accel, 1e-15);
  EXPECT_NEAR(m.rateMagnitude(start + ramp + 5), max_rate, 1e-15);
  EXPECT_NEAR(m.rateMagnitude(m.endTime() - 1), accel, 1e-15);
  EXPECT_EQ(m.rateMagnitude(m.endTime() + 1), 0.0);
  // Total angle = area of the trapezoid = max_rate * (ramp + coast), then it holds still.
  const double total = max_rate * (ramp + coast);
  EXPECT_NEAR(m.angle(m.endTime()), total, 1e-14);
  EXPECT_NEAR(attitudeError(m.attitude(0), m.attitude(m.endTime() + 50)).total, total, 1e-12);
  EXPECT_NEAR(attitudeError(m.attitude(m.endTime()), m.attitude(m.endTime() + 50)).total, 0, 1e-15);
}

TEST(Motion, TumbleConservesEnergyAndInertialMomentum) {
  const Vec3 I(1.0, 2.0, 3.0);
  // Mostly about the intermediate axis: it flips (Dzhanibekov), a hard case for integration.
  const TumbleMotion m(kQ0, Vec3(0.01, 0.5, 0.01), I);
  const Vec3 w0 = m.rateBody(0);
  const double e0 = w0.dot(I.cwiseProduct(w0));
  const Vec3 h0 = m.attitude(0) * I.cwiseProduct(w0);  // inertial angular momentum
  double min_wy = 1e9;
  for (double t = 0; t <= 60; t += 0.25) {
    const Vec3 w = m.rateBody(t);
    min_wy = std::min(min_wy, w.y());
    EXPECT_NEAR(w.dot(I.cwiseProduct(w)), e0, 1e-10 * e0) << t;
    const Vec3 h = m.attitude(t) * I.cwiseProduct(w);
    EXPECT_LT((h - h0).norm(), 1e-10 * h0.norm()) << t;
  }
  EXPECT_LT(min_wy, -0.4);  // the intermediate-axis rate reversed: real tumbling
}

TEST(Motion, QueriesDoNotDependOnOrder) {
  const JitterMotion a(kQ0, Vec3::Zero(), Vec3(0.01, 0.02, 0.03), Vec3(1, 2, 3), Vec3::Zero());
  const JitterMotion b(kQ0, Vec3::Zero(), Vec3(0.01, 0.02, 0.03), Vec3(1, 2, 3), Vec3::Zero());
  (void)b.attitude(200.0);  // fills b's cache far ahead
  for (double t : {0.0, 0.0123, 5.5, 77.7, 150.0001}) {
    EXPECT_EQ(a.attitude(t).coeffs(), b.attitude(t).coeffs()) << t;
  }
  // Negative times integrate backwards and stay consistent with the rate.
  const double d = 1e-4;
  const Vec3 num = quatLog(a.attitude(-0.5 - d).conjugate() * a.attitude(-0.5 + d)) / (2 * d);
  EXPECT_LT((num - a.rateBody(-0.5)).norm(), 1e-8);
}

TEST(Motion, FromConfigBuildsEveryType) {
  mrpt::config::CConfigFileMemory cfg(std::string(
      "[hold]\ntype=hold\nra_deg=40\ndec_deg=-25\nroll_deg=10\n"
      "[slew]\ntype=slew\nrate_deg_s=0 0 2\n"
      "[accel]\ntype=slew_accel\naxis=0,1,0\nmax_rate_deg_s=2\naccel_deg_s2=0.5\ncoast_s=4\n"
      "[jitter]\ntype=jitter\namplitude_deg_s=0.01 0.01 0.02\nfrequency_hz=1 2 5\n"
      "[tumble]\ntype=tumble\nrate_deg_s=1 10 1\ninertia=10 20 30\nstep_s=0.002\n"));
  const auto hold = MotionProfile::fromConfig(cfg, "hold");
  EXPECT_EQ(hold->type(), "hold");
  EXPECT_LT(attitudeError(hold->attitude(3), kQ0).total, 1e-12);
  const auto slew = MotionProfile::fromConfig(cfg, "slew");
  EXPECT_NEAR(slew->rateBody(1).z(), deg2rad(2.0), 1e-15);
  const auto accel = MotionProfile::fromConfig(cfg, "accel");
  EXPECT_NEAR(accel->rateBody(6).y(), deg2rad(2.0), 1e-15);  // coasting (ramp 4 s)
  EXPECT_EQ(MotionProfile::fromConfig(cfg, "jitter")->type(), "jitter");
  const auto tumble = MotionProfile::fromConfig(cfg, "tumble");
  EXPECT_NEAR(tumble->rateBody(0).y(), deg2rad(10.0), 1e-15);
  EXPECT_EQ(MotionProfile::types().size(), 5u);
}

TEST(Motion, FromConfigRejectsBadInputNamingTheKey) {
  mrpt::config::CConfigFileMemory cfg(std::string(
      "[a]\ntype=spin\n[b]\ntype=slew\n[c]\ntype=slew\nrate_deg_s=1 2\n"
      "[d]\ntype=slew_accel\nmax_rate_deg_s=1\naccel_deg_s2=-1\n[e]\ntype=hold\ndec_deg=abc\n"));
  auto message = [&](const std::string& s) {
    try {
      MotionProfile::fromConfig(cfg, s);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  EXPECT_NE(message("a").find("'type' = 'spin'"), std::string::npos) << message("a");
  EXPECT_NE(message("b").find("rate_deg_s"), std::string::npos) << message("b");
  EXPECT_NE(message("c").find("three numbers"), std::string::npos) << message("c");
  EXPECT_NE(message("d").find("accel_deg_s2"), std::string::npos) << message("d");
  EXPECT_NE(message("e").find("dec_deg"), std::string::npos) << message("e");
}

}  // namespace
}  // namespace st
