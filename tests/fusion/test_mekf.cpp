// AttitudeMekf unit tests: propagation against an independent RK4 truth, the transition
// matrix and the star-vector Jacobian against finite differences, covariance growth against
// its closed form, update shrinkage, one/two-star geometry and consistency, gating.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

#include "common/attitude.hpp"
#include "common/conventions.hpp"
#include "fusion/consistency.hpp"
#include "fusion/mekf.hpp"
#include "sensors/sim/gyro_model.hpp"
#include "sensors/sim/motion.hpp"

namespace st {
namespace {

const Quat kQ0 = attitudeFromRaDecRoll({deg2rad(200.0), deg2rad(15.0), deg2rad(33.0)});

Vec3 gaussian3(std::mt19937_64& rng, double sigma) {
  std::normal_distribution<double> n(0.0, sigma);
  return Vec3(n(rng), n(rng), n(rng));
}

// Independent truth: RK4 on q_dot = 1/2 q (x) (0, w(t)) from MotionProfile::rateBody only.
Quat rk4Truth(const MotionProfile& m, double t_end, double h) {
  auto f = [&](double t, const Eigen::Vector4d& s) {
    const Vec3 w = m.rateBody(t);
    const Quat d = Quat(s[0], s[1], s[2], s[3]) * Quat(0, w.x(), w.y(), w.z());
    return Eigen::Vector4d(0.5 * d.w(), 0.5 * d.x(), 0.5 * d.y(), 0.5 * d.z());
  };
  const Quat q0 = m.attitude(0);
  Eigen::Vector4d s(q0.w(), q0.x(), q0.y(), q0.z());
  const int n = static_cast<int>(std::round(t_end / h));
  for (int i = 0; i < n; ++i) {
    const double t = i * h;
    const Eigen::Vector4d k1 = f(t, s), k2 = f(t + h / 2, s + h / 2 * k1),
                          k3 = f(t + h / 2, s + h / 2 * k2), k4 = f(t + h, s + h * k3);
    s += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    s.normalize();
  }
  return Quat(s[0], s[1], s[2], s[3]);
}

TEST(Mekf, OptionsValidation) {
  std::string err;
  EXPECT_TRUE(MekfOptions().isValid(&err));
  MekfOptions o;
  o.gate_probability = 1.0;
  EXPECT_FALSE(o.isValid(&err));
  EXPECT_NE(err.find("gate_probability"), std::string::npos);
  o = MekfOptions();
  o.arw_rad_rt_s = -1;
  EXPECT_FALSE(o.isValid(&err));
  const MekfOptions d = MekfOptions::fromDatasheet(0.1, 0.5, 10);
  EXPECT_NEAR(d.arw_rad_rt_s, deg2rad(0.1) / 60, 1e-18);
  EXPECT_NEAR(d.rrw_rad_s_rt_s, deg2rad(0.5) / 3600 / 60, 1e-20);
  EXPECT_NEAR(d.initial_bias_sigma_rad_s, deg2rad(10) / 3600, 1e-18);
}

TEST(Mekf, PropagationMatchesIndependentRk4Truth) {
  const JitterMotion motion(kQ0, Vec3(0.02, -0.03, 0.05), Vec3(0.01, 0.02, 0.015),
                            Vec3(0.5, 1.7, 3.1), Vec3(0.3, 0.0, 1.0));
  GyroParams gp{};
  gp.rate_hz = 100;
  const Vec3 bias(2e-5, -1e-5, 3e-5);  // known to the filter: subtracting it is exact
  GyroSimulator gyro(gp, 1, bias);
  AttitudeMekf f(MekfOptions{});
  f.initialize(0, kQ0, Mat3::Identity() * 1e-10, bias);
  const double T = 30, dt = 0.01;
  for (int k = 0; k < T / dt; ++k)
    ASSERT_TRUE(f.propagate(gyro.sample(motion, k * dt, (k + 1) * dt), (k + 1) * dt));
  const Quat truth = rk4Truth(motion, T, 2e-4);
  const double err = attitudeError(f.attitude(), truth).total;
  std::printf("propagation vs RK4 truth after %.0f s: %.3g rad\n", T, err);
  EXPECT_LT(err, 1e-10);
}

TEST(Mekf, TransitionMatchesNumericJacobian) {
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 20; ++trial) {
    const Quat qhat = canonical(quatExp(gaussian3(rng, 1.0)));
    const Vec3 bhat = gaussian3(rng, 0.01);
    const Vec3 wmeas = gaussian3(rng, trial < 10 ? 0.5 : 1e-6);  // large and tiny rates
    const double dt = 0.05;
    auto propagateErr = [&](const Vec6& x) {
      const Quat q = qhat * quatExp(x.head<3>());
      const Vec3 b = bhat + x.tail<3>();
      const Quat qh1 = qhat * quatExp((wmeas - bhat) * dt);
      const Quat q1 = q * quatExp((wmeas - b) * dt);
      Vec6 e;
      e << quatLog(qh1.conjugate() * q1), x.tail<3>();
      return e;
    };
    Mat6 num;
    const double eps = 1e-6;
    for (int j = 0; j < 6; ++j) {
      Vec6 dx = Vec6::Zero();
      dx[j] = eps;
      num.col(j) = (propagateErr(dx) - propagateErr(-dx)) / (2 * eps);
    }
    const Mat6 Phi = AttitudeMekf::transition(wmeas - bhat, dt);
    EXPECT_LT((Phi - num).cwiseAbs().maxCoeff(), 1e-8) << trial << "\n" << Phi << "\n" << num;
  }
}

TEST(Mekf, StarVectorJacobianMatchesFiniteDifferences) {
  std::mt19937_64 rng(6);
  for (int trial = 0; trial < 50; ++trial) {
    const Quat q = canonical(quatExp(gaussian3(rng, 2.0)));
    const Vec3 r = gaussian3(rng, 1.0).normalized();
    Eigen::Matrix<double, 2, 3> E, H;
    const Vec3 b_pred = AttitudeMekf::starVectorModel(q, r, &E, &H);
    EXPECT_LT((E * b_pred).norm(), 1e-14);
    EXPECT_LT((E * E.transpose() - Eigen::Matrix2d::Identity()).norm(), 1e-14);
    Eigen::Matrix<double, 2, 3> num;
    const double eps = 1e-6;
    for (int j = 0; j < 3; ++j) {
      const Vec3 d = Vec3::Unit(j) * eps;
      const Vec3 bp = (q * quatExp(d)).conjugate() * r, bm = (q * quatExp(-d)).conjugate() * r;
      num.col(j) = E * (bp - bm) / (2 * eps);
    }
    EXPECT_LT((H - num).cwiseAbs().maxCoeff(), 1e-9) << trial;
  }
}

TEST(Mekf, CovarianceGrowthWithoutMeasurementsMatchesClosedForm) {
  // At zero rate, P11(t) = pa + pb t^2 + sv^2 t + su^2 t^3 / 3 exactly (M&C sec. 6.2.4).
  MekfOptions o;
  o.arw_rad_rt_s = 3e-5;
  o.rrw_rad_s_rt_s = 2e-7;
  o.initial_bias_sigma_rad_s = 1e-5;
  AttitudeMekf f(o);
  const double pa = 1e-8, pb = 1e-10;
  f.initialize(0, kQ0, Mat3::Identity() * pa);
  double prev = 0;
  for (int k = 1; k <= 1000; ++k) {
    f.propagate(Vec3::Zero(), k * 0.1);
    const double P11 = f.covariance()(0, 0);
    EXPECT_GT(P11, prev);
    prev = P11;
  }
  const double t = 100;
  const double expected = pa + pb * t * t + o.arw_rad_rt_s * o.arw_rad_rt_s * t +
                          o.rrw_rad_s_rt_s * o.rrw_rad_s_rt_s * t * t * t / 3;
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(f.covariance()(a, a) / expected, 1.0, 1e-12);
  EXPECT_NEAR(f.covariance()(3, 3), pb + o.rrw_rad_s_rt_s * o.rrw_rad_s_rt_s * t, 1e-22);
  // Under rotation the trace still grows (it cannot shrink without measurements).
  const double tr = f.attitudeCov().trace();
  f.propagate(Vec3(0.3, -0.2, 0.5), 101);
  EXPECT_GT(f.attitudeCov().trace(), tr);
}

TEST(Mekf, UpdatesShrinkCovarianceAndKeepItSymmetricPd) {
  MekfOptions o = MekfOptions::fromDatasheet(0.1, 0.1, 10);
  AttitudeMekf f(o);
  f.initialize(0, kQ0, Mat3::Identity() * 1e-6);
  const Mat6 P0 = f.covariance();
  const Mat3 R = Vec3(1e-9, 1e-9, 2e-8).asDiagonal();
  const MekfUpdateResult u = f.updateAttitude(kQ0 * quatExp(Vec3(1e-5, -2e-5, 1e-4)), R);
  ASSERT_TRUE(u.accepted) << u.reason;
  EXPECT_EQ(u.dof, 3);
  EXPECT_LT((u.innovation_cov - (P0.topLeftCorner<3, 3>() + R)).norm(), 1e-20);
  const Mat6 dP = P0 - f.covariance();
  EXPECT_GE(Eigen::SelfAdjointEigenSolver<Mat6>(dP).eigenvalues().minCoeff(), -1e-18);
  for (int a = 0; a < 3; ++a) EXPECT_LT(f.covariance()(a, a), R(a, a) * 1.0001);
  EXPECT_EQ(f.covariance(), f.covariance().transpose());
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Mat6>(f.covariance()).eigenvalues().minCoeff(), 0);
  const MekfStep s = f.step();
  EXPECT_EQ(s.event, MekfStep::Event::kAttitudeFix);
  EXPECT_NEAR(s.sigma_attitude.x(), std::sqrt(f.covariance()(0, 0)), 1e-18);
  EXPECT_GT(s.update.nis, 0);
}

TEST(Mekf, OneStarLeavesRotationAboutItUnobserved) {
  AttitudeMekf f(MekfOptions{});
  const double p = 1e-6;
  f.initialize(0, kQ0, Mat3::Identity() * p);
  const Vec3 b(0.1, -0.05, 1.0);
  const Vec3 bn = b.normalized();
  const Vec3 r = kQ0 * bn;
  const auto u = f.updateStarVectors({StarVectorMeasurement::fromSigma(bn, r, 1e-4)});
  ASSERT_TRUE(u.accepted) << u.reason;
  EXPECT_EQ(u.dof, 2);
  const Mat3 P = f.attitudeCov();
  EXPECT_NEAR(bn.dot(P * bn), p, 1e-12 * p);  // about the line of sight: no information
  const Vec3 across = bn.cross(Vec3::UnitX()).normalized();
  EXPECT_LT(across.dot(P * across), 0.02 * p);  // across it: close to the star's sigma^2
}

TEST(Mekf, TwoStarUpdatesAreConsistent) {
  // 1000 independent single updates with two stars: posterior attitude NEES (3 dof) and
  // NIS (4 dof) averages inside their two-sided 99 % chi-square bands.
  std::mt19937_64 rng(8);
  const int n = 1000;
  const double sigma_prior = 2e-4, sigma_star = 5e-5;
  double nees = 0, nis = 0;
  for (int i = 0; i < n; ++i) {
    const Quat q_true = canonical(quatExp(gaussian3(rng, 2.0)));
    const Quat q_est = q_true * quatExp(-gaussian3(rng, sigma_prior));
    MekfOptions o;
    o.gate_enabled = false;  // a 0.1 % gate would cut the tail this test measures
    AttitudeMekf f(o);
    f.initialize(0, q_est, Mat3::Identity() * sigma_prior * sigma_prior);
    std::vector<StarVectorMeasurement> stars;
    for (const Vec3& b_true :
         {Vec3(0.05, 0.02, 1).normalized(), Vec3(-0.1, 0.08, 1).normalized()}) {
      const Vec3 r = q_true * b_true;
      // noise across the line of sight only
      Vec3 noise = gaussian3(rng, sigma_star);
      noise -= b_true * b_true.dot(noise);
      stars.push_back(
          StarVectorMeasurement::fromSigma((b_true + noise).normalized(), r, sigma_star));
    }
    const auto u = f.updateStarVectors(stars);
    ASSERT_TRUE(u.accepted) << u.reason;
    nis += u.nis / n;
    nees += attitudeNees(f.attitude(), f.attitudeCov(), q_true) / n;
  }
  const ChiSquareBand b3 = averagedChiSquareBand(3, n, 0.99),
                      b4 = averagedChiSquareBand(4, n, 0.99);
  std::printf("two stars: mean NEES %.3f in [%.3f, %.3f], mean NIS %.3f in [%.3f, %.3f]\n", nees,
              b3.lo, b3.hi, nis, b4.lo, b4.hi);
  EXPECT_TRUE(b3.contains(nees));
  EXPECT_TRUE(b4.contains(nis));
}

TEST(Mekf, GateRejectsOutliersAndCountsThem) {
  AttitudeMekf f(MekfOptions{});
  f.initialize(0, kQ0, Mat3::Identity() * 1e-8);
  const Quat before = f.attitude();
  const Mat6 P = f.covariance();
  const auto u = f.updateAttitude(kQ0 * quatExp(Vec3(0, 0.01, 0)), Mat3::Identity() * 1e-8);
  EXPECT_FALSE(u.accepted);
  EXPECT_NE(u.reason.find("chi-square gate"), std::string::npos) << u.reason;
  EXPECT_GT(u.nis, u.gate);
  EXPECT_EQ(f.rejectedUpdates(), 1);
  EXPECT_EQ(f.acceptedUpdates(), 0);
  EXPECT_EQ(f.attitude().coeffs(), before.coeffs());
  EXPECT_EQ(f.covariance(), P);
  // A star 0.01 rad off its predicted place is rejected too; a good one is accepted.
  const Vec3 bn = Vec3(0, 0, 1);
  const auto bad = f.updateStarVectors(
      {StarVectorMeasurement::fromSigma(bn, kQ0 * quatExp(Vec3(0.01, 0, 0)) * bn, 1e-4)});
  EXPECT_FALSE(bad.accepted);
  const auto good = f.updateStarVectors({StarVectorMeasurement::fromSigma(bn, kQ0 * bn, 1e-4)});
  EXPECT_TRUE(good.accepted) << good.reason;
  EXPECT_EQ(f.rejectedUpdates(), 2);
  EXPECT_EQ(f.acceptedUpdates(), 1);
  EXPECT_NEAR(f.gateThreshold(3), chiSquareQuantile(0.999, 3), 1e-12);
}

// The lock-out a gate alone allows: the filter's prior is 5 sigma off and dominates S, so
// every later fix of the true attitude is rejected too; resetAttitude restarts the attitude
// from a fix while keeping the bias estimate and its covariance.
TEST(Mekf, GateLockOutIsCountedAndResetAttitudeRecovers) {
  AttitudeMekf f(MekfOptions::fromDatasheet(0.3, 3.0, 20));
  const double sigma = 1e-3;  // prior 1-sigma [rad], fixes 5 arcsec
  const Mat3 R = Mat3::Identity() * std::pow(arcsec2rad(5), 2);
  f.initialize(0, kQ0 * quatExp(Vec3(5 * sigma, 0, 0)), Mat3::Identity() * sigma * sigma,
               Vec3(1e-6, -2e-6, 3e-6));
  for (int k = 1; k <= 5; ++k) {
    ASSERT_TRUE(f.propagate(f.bias(), 0.2 * k));  // the true rate is zero
    EXPECT_FALSE(f.updateAttitude(kQ0, R).accepted) << "fix " << k;
    EXPECT_EQ(f.consecutiveRejections(), k);
  }
  const Vec3 bias = f.bias();
  const Mat3 P_bb = f.covariance().bottomRightCorner<3, 3>();
  f.resetAttitude(1.0, kQ0, R);
  EXPECT_EQ(f.consecutiveRejections(), 0);
  EXPECT_EQ(f.time(), 1.0);
  EXPECT_LT(attitudeError(f.attitude(), kQ0).total, 1e-12);
  EXPECT_EQ(f.bias(), bias);
  EXPECT_EQ(Mat3(f.covariance().bottomRightCorner(3, 3)), P_bb);
  EXPECT_EQ(f.attitudeCov(), R);
  EXPECT_EQ(Mat3(f.covariance().topRightCorner(3, 3)), Mat3::Zero());
  ASSERT_TRUE(f.propagate(f.bias(), 1.2));
  EXPECT_TRUE(f.updateAttitude(kQ0, R).accepted);
  // An accepted update ends a run of rejections.
  EXPECT_FALSE(f.updateAttitude(kQ0 * quatExp(Vec3(0, 0.01, 0)), R).accepted);
  EXPECT_EQ(f.consecutiveRejections(), 1);
  EXPECT_TRUE(f.updateAttitude(kQ0, R).accepted);
  EXPECT_EQ(f.consecutiveRejections(), 0);
  // Before initialisation there is no bias to keep: the reset initialises with the prior.
  AttitudeMekf g(f.options());
  g.resetAttitude(0, kQ0, R);
  ASSERT_TRUE(g.initialized());
  EXPECT_DOUBLE_EQ(std::sqrt(g.covariance()(3, 3)), g.options().initial_bias_sigma_rad_s);
}

TEST(Mekf, PredictAtLeavesTheFilterAloneAndMatchesPredictTo) {
  AttitudeMekf f(MekfOptions::fromDatasheet(0.2, 0.2, 5));
  f.initialize(10, kQ0, Mat3::Identity() * 1e-8);
  ASSERT_TRUE(f.propagate(Vec3(0.01, 0.02, -0.03), 10.02));
  const MekfPrediction p = f.predictAt(10.1);
  EXPECT_EQ(f.time(), 10.02);
  ASSERT_TRUE(f.predictTo(10.1));
  EXPECT_LT(attitudeError(p.q_ib, f.attitude()).total, 1e-15);
  EXPECT_LT((p.P - f.covariance()).norm(), 1e-20);
  EXPECT_GT(p.attitudeCov().trace(), 3e-8);
  std::string why;
  EXPECT_FALSE(f.propagate(Vec3::Zero(), 10.1, &why));  // duplicate time
  EXPECT_NE(why.find("out of order"), std::string::npos);
  EXPECT_FALSE(f.propagate(Vec3::Zero(), 9.0, &why));  // out of order
  AttitudeMekf g(MekfOptions{});
  EXPECT_FALSE(g.propagate(Vec3::Zero(), 1.0, &why));
  EXPECT_FALSE(g.updateAttitude(kQ0, Mat3::Identity()).accepted);
}

}  // namespace
}  // namespace st
