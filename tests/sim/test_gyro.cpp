// Simulated gyro: noiseless samples integrate back to the truth; the Allan deviation shows
// the angle random walk (sigma(tau) = N / sqrt(tau)) and the rate random walk
// (sigma(tau) = K sqrt(tau/3)) of the datasheet parameters (IEEE Std 952 Annex C); the bias
// random walk has variance sigma_u^2 t; constant bias and scale factor show in the mean.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>
#include <vector>

#include "common/attitude.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "sensors/sim/gyro_model.hpp"
#include "sensors/sim/motion.hpp"

namespace st {
namespace {

const Quat kQ0 = attitudeFromRaDecRoll({deg2rad(120.0), deg2rad(35.0), deg2rad(-40.0)});

GyroParams params(double rate_hz, double arw, double rrw, double bias = 0) {
  GyroParams p;
  p.rate_hz = rate_hz;
  p.arw_deg_rt_h = arw;
  p.rrw_deg_h_rt_h = rrw;
  p.bias_deg_h = bias;
  return p;
}

/// Static record of one axis per column: n samples at rate p.rate_hz.
std::vector<Vec3> record(const GyroParams& p, uint64_t seed, int n) {
  const HoldMotion hold(kQ0);
  GyroSimulator g(p, seed, Vec3::Zero());
  std::vector<Vec3> out(n);
  const double dt = 1.0 / p.rate_hz;
  for (int k = 0; k < n; ++k) out[k] = g.sample(hold, k * dt, (k + 1) * dt);
  return out;
}

/// Overlapping Allan deviation of axis `a` at tau = m * dt from the integrated angle
/// theta_k: sigma^2 = sum (theta_k+2m - 2 theta_k+m + theta_k)^2 / (2 tau^2 (N - 2m)).
double allanDeviation(const std::vector<Vec3>& rates, int a, double dt, int m) {
  std::vector<double> theta(rates.size() + 1, 0.0);
  for (std::size_t k = 0; k < rates.size(); ++k) theta[k + 1] = theta[k] + rates[k][a] * dt;
  const std::size_t n = theta.size();
  double sum = 0;
  for (std::size_t k = 0; k + 2 * m < n; ++k) {
    const double d = theta[k + 2 * m] - 2 * theta[k + m] + theta[k];
    sum += d * d;
  }
  const double tau = m * dt;
  return std::sqrt(sum / (2 * tau * tau * (n - 2 * m)));
}

TEST(Gyro, NoiselessSamplesIntegrateToTheTruth) {
  const JitterMotion jitter(kQ0, Vec3(0.02, -0.01, 0.03), Vec3(0.01, 0.02, 0.005),
                            Vec3(0.7, 3.0, 11.0), Vec3(0, 1, 2));
  const TumbleMotion tumble(kQ0, Vec3(0.1, 0.6, 0.05), Vec3(1, 2, 3));
  for (const MotionProfile* m :
       {static_cast<const MotionProfile*>(&jitter), static_cast<const MotionProfile*>(&tumble)}) {
    GyroSimulator g(params(50, 0, 0), 7, Vec3::Zero());
    Quat q = m->attitude(0);
    const double dt = 0.02;
    for (int k = 0; k < 1500; ++k) q = q * quatExp(g.sample(*m, k * dt, (k + 1) * dt) * dt);
    EXPECT_LT(attitudeError(q, m->attitude(1500 * dt)).total, 1e-10) << m->type();
  }
}

TEST(Gyro, AllanDeviationAtOneSecondMatchesArw) {
  const double arw = 0.15;  // deg/sqrt(h)
  const GyroParams p = params(100, arw, 0);
  const int n = 100 * 3000;  // 3000 s: ~1.3 % standard error of ADEV(1 s) per axis
  const std::vector<Vec3> rates = record(p, 11, n);
  const double expected = p.sigmaV();  // N / sqrt(1 s)
  for (int a = 0; a < 3; ++a) {
    const double adev = allanDeviation(rates, a, 0.01, 100);
    std::printf("axis %d: ADEV(1 s) = %.4f deg/h, expected %.4f deg/h\n", a, rad2deg(adev) * 3600,
                rad2deg(expected) * 3600);
    EXPECT_NEAR(adev / expected, 1.0, 0.10) << a;
    // Teeth: a gyro with 25 % more ARW is told apart by the same tolerance.
    EXPECT_GT(std::abs(adev / (1.25 * expected) - 1.0), 0.10) << a;
    // The white-noise slope -1/2 between tau = 0.1 s and 10 s.
    const double slope =
        std::log(allanDeviation(rates, a, 0.01, 1000) / allanDeviation(rates, a, 0.01, 10)) /
        std::log(100.0);
    EXPECT_NEAR(slope, -0.5, 0.05) << a;
  }
}

TEST(Gyro, RateRandomWalkSlopeAndLevel) {
  // RRW dominated: sigma^2(tau) = N^2/tau + K^2 tau / 3.
  const GyroParams p = params(10, 0.005, 2.0);
  const int n = 10 * 40000;  // 40000 s
  const std::vector<Vec3> rates = record(p, 12, n);
  const double N = p.sigmaV(), K = p.sigmaU();
  for (int a = 0; a < 3; ++a) {
    const double s1 = allanDeviation(rates, a, 0.1, 500);   // tau = 50 s
    const double s2 = allanDeviation(rates, a, 0.1, 4000);  // tau = 400 s
    const double e1 = std::sqrt(N * N / 50 + K * K * 50 / 3);
    std::printf("axis %d: ADEV(50 s) = %.4f deg/h (model %.4f), slope 50->400 s = %.3f\n", a,
                rad2deg(s1) * 3600, rad2deg(e1) * 3600, std::log(s2 / s1) / std::log(8.0));
    EXPECT_NEAR(s1 / e1, 1.0, 0.15) << a;  // ~4 % standard error at T/tau = 800
    EXPECT_NEAR(std::log(s2 / s1) / std::log(8.0), 0.5, 0.15) << a;
  }
}

TEST(Gyro, BiasRandomWalkVarianceGrowsAsSigmaUSquaredT) {
  // b(T) - b(0) ~ N(0, sigma_u^2 T) per axis; 100 runs x 3 axes = 300 samples.
  const GyroParams p = params(20, 0.1, 5.0);
  const HoldMotion hold(kQ0);
  const double T = 200;
  double sum_sq = 0;
  int count = 0;
  for (uint64_t seed = 100; seed < 200; ++seed) {
    GyroSimulator g(p, seed, Vec3::Zero());
    for (int k = 0; k < T * p.rate_hz; ++k) g.sample(hold, k / p.rate_hz, (k + 1) / p.rate_hz);
    sum_sq += g.bias().squaredNorm();
    count += 3;
  }
  const double ratio = sum_sq / count / (p.sigmaU() * p.sigmaU() * T);
  // chi2(300)/300 two-sided 99.9 %: [0.76, 1.28].
  std::printf("bias walk variance ratio = %.3f\n", ratio);
  EXPECT_GT(ratio, 0.76);
  EXPECT_LT(ratio, 1.28);
}

TEST(Gyro, ConstantBiasAndScaleFactorShowInTheMean) {
  GyroParams p = params(100, 0.05, 0, 36.0);  // 36 deg/h = 0.01 deg/s
  p.scale_factor_ppm = 2000;
  const Vec3 w(0.01, -0.02, 0.03);
  const SlewMotion slew(kQ0, w);
  const Vec3 turn_on(1e-5, -2e-5, 0);
  GyroSimulator g(p, 3, turn_on);
  Vec3 mean = Vec3::Zero();
  const int n = 20000;
  for (int k = 0; k < n; ++k) mean += g.sample(slew, k * 0.01, (k + 1) * 0.01) / n;
  const Vec3 expected = 1.002 * w + turn_on + Vec3::Constant(deg2rad(0.01));
  const double se = p.sigmaV() / std::sqrt(0.01) / std::sqrt(double(n));  // standard error
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(mean[a], expected[a], 4 * se) << a;
  EXPECT_LT((g.bias() - turn_on - Vec3::Constant(deg2rad(0.01))).norm(), 1e-18);
}

TEST(Gyro, QuantisationKeepsTheIntegratedAngle) {
  GyroParams p = params(100, 0, 0);
  p.quantum_rad_s = 1e-4;
  const Vec3 w(0.012345, -0.00678, 0.0003);
  const SlewMotion slew(kQ0, w);
  GyroSimulator g(p, 1, Vec3::Zero());
  Vec3 angle = Vec3::Zero();
  for (int k = 0; k < 1000; ++k) {
    const Vec3 s = g.sample(slew, k * 0.01, (k + 1) * 0.01);
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(s[a] / 1e-4, std::round(s[a] / 1e-4), 1e-9);  // multiples of the quantum
    angle += s * 0.01;
  }
  // Remainder carried: integrated angle within half a quantum-step of the truth.
  EXPECT_LT((angle - w * 10.0).cwiseAbs().maxCoeff(), 0.5e-4 * 0.01 + 1e-15);
}

TEST(Gyro, DeterministicForASeed) {
  const GyroParams p = params(100, 0.1, 1.0, 3);
  const auto a = record(p, 42, 500), b = record(p, 42, 500), c = record(p, 43, 500);
  for (int k = 0; k < 500; ++k) EXPECT_EQ(a[k], b[k]);
  EXPECT_NE(a[10], c[10]);
}

TEST(Gyro, FromConfig) {
  mrpt::config::CConfigFileMemory cfg(
      std::string("[gyro]\nrate_hz=200\narw_deg_rt_h=0.1\nrrw_deg_h_rt_h=0.5\nbias_deg_h=-2\n"
                  "scale_factor_ppm=100\n[bad]\nrate_hz=0\n[bad2]\nrate_hz=10\narw_deg_rt_h=x\n"));
  const GyroParams p = GyroParams::fromConfig(cfg, "gyro");
  EXPECT_EQ(p.rate_hz, 200);
  EXPECT_NEAR(p.sigmaV(), deg2rad(0.1) / 60, 1e-18);
  EXPECT_NEAR(p.sigmaU(), deg2rad(0.5) / 3600 / 60, 1e-20);
  EXPECT_NEAR(p.constantBias(), -deg2rad(2.0) / 3600, 1e-18);
  EXPECT_EQ(p.scale_factor_ppm, 100);
  EXPECT_EQ(p.quantum_rad_s, 0);
  EXPECT_THROW(GyroParams::fromConfig(cfg, "bad"), InputError);
  EXPECT_THROW(GyroParams::fromConfig(cfg, "bad2"), InputError);
  EXPECT_THROW(GyroParams::fromConfig(cfg, "missing"), InputError);
}

}  // namespace
}  // namespace st
