// Monte Carlo consistency of the gyroless filter (issue 16 item 1 acceptance; Bar-Shalom et al.
// sec. 5.4), through the one fusion loop (fusion/fusion_loop.hpp) with synthetic fixes.
// 50 runs of 10 minutes, no gyro: the true body rate starts from the filter's prior (0.25 deg/s
// per axis) and random-walks with the filter's density (sw = 2e-4 rad/s^2/sqrt(Hz): 0.28
// deg/s per axis over 10 minutes), so the rates reach ~1 deg/s and change all the time;
// fixes at 10 Hz are the truth perturbed by their covariance (5, 5, 40 arcsec).
//  - run-averaged attitude NEES, rate NEES (3 dof each, every fix time) and NIS (3 dof) inside
//    the two-sided 95 % chi-square band of 50 runs for at least the one-sided 99 % lower
//    limit of that fraction (derivation in test_mekf_montecarlo.cpp: NIS as independent
//    Bernoulli(0.95), NEES from 6 batch means: the averaged NEES of neighbouring steps is
//    correlated through the filter);
//  - the same filter with its rate walk 100x too small fails the rate-NEES test (its rate
//    covariance shrinks below the true wander).
// Env: ST_MC_SEED=<offset> reruns with other seeds.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cstdlib>
#include <random>

#include "common/attitude.hpp"
#include "common/conventions.hpp"
#include "fusion/consistency.hpp"
#include "fusion/fusion_loop.hpp"
#include "sensors/sim/random_streams.hpp"

namespace st {
namespace {

constexpr int kRuns = 50;
constexpr double kDuration = 600;  // [s]
constexpr double kTruthDt = 0.005;  // truth integration step [s]
constexpr int kFixEvery = 20;       // 10 Hz fixes
constexpr int kSteps = static_cast<int>(kDuration / kTruthDt + 0.5);
constexpr double kRateWalk = 2e-4;   // [rad/s^2/sqrt(Hz)]
constexpr double kRateSigma0 = 0.25; // [deg/s] prior and initial truth spread per axis
const Mat3 kFixCov =
    Vec3(std::pow(arcsec2rad(5), 2), std::pow(arcsec2rad(5), 2), std::pow(arcsec2rad(40), 2))
        .asDiagonal();

struct McResult {
  std::vector<double> nees_att, nees_rate, nis;  // run-averaged, per fix time
  int rejected = 0;
  double max_rate_deg_s = 0;   // largest true |w| of all runs
  double rms_rate_err = 0;     // [deg/s] total rate error after the first 10 s
};

McResult runMonteCarlo(double walk_scale) {
  FusionOptions fo;
  fo.filter.model = MekfOptions::Model::kGyroless;
  fo.filter.rate_walk_rad_s2_rt_hz = kRateWalk * walk_scale;
  fo.filter.initial_rate_sigma_rad_s = deg2rad(kRateSigma0);
  fo.reorder_window_s = 0;
  const int n_fix = kSteps / kFixEvery;
  McResult res;
  res.nees_att.assign(n_fix, 0.0);
  res.nees_rate.assign(n_fix, 0.0);
  res.nis.assign(n_fix, 0.0);
  double se = 0;
  long n_se = 0;
  const int off = std::getenv("ST_MC_SEED") ? std::atoi(std::getenv("ST_MC_SEED")) : 0;
  for (int run = 0; run < kRuns; ++run) {
    std::mt19937_64 rng(splitMix64(7000 + run + off));
    std::normal_distribution<double> n01;
    auto normal3 = [&] { return Vec3(n01(rng), n01(rng), n01(rng)); };
    Quat q = attitudeFromRaDecRoll({deg2rad(30.0 + run), deg2rad(-20.0), deg2rad(5.0)});
    Vec3 w = normal3() * deg2rad(kRateSigma0);
    // The rate "at" a grid time: the mean of the steps' rates before and after it (each held
    // over its step), which the continuous-time w(t) of the filter lies between.
    Vec3 w_at = w;
    FusionLoop loop(fo);
    int fix_index = -1;
    loop.setStepCallback([&](const FusionStep& s) {
      if (!s.filter.initialized || fix_index < 0) return;
      const Vec3 ea = attitudeError(s.filter.q_ib, q).rotvec_body;
      const Vec3 ew = w_at - s.filter.rate;
      const Mat6& P = s.filter.P;
      res.nees_att[fix_index] += ea.dot(P.topLeftCorner<3, 3>().ldlt().solve(ea)) / kRuns;
      res.nees_rate[fix_index] += ew.dot(P.bottomRightCorner<3, 3>().ldlt().solve(ew)) / kRuns;
      if (s.use == FixUse::kAccepted || s.use == FixUse::kRejected)
        res.nis[fix_index] += s.update.nis / kRuns;
      res.rejected += s.use == FixUse::kRejected;
      if (s.t > 10) {
        se += ew.squaredNorm();
        ++n_se;
      }
    });
    for (int k = 0; k <= kSteps; ++k) {
      const double t = k * kTruthDt;
      if (k > 0) {
        // Rate constant over the step, then its random-walk increment (the filter's model).
        q = canonical(q * quatExp(w * kTruthDt));
        const Vec3 w_before = w;
        w += normal3() * kRateWalk * std::sqrt(kTruthDt);
        w_at = 0.5 * (w_before + w);
      }
      res.max_rate_deg_s = std::max(res.max_rate_deg_s, rad2deg(w.norm()));
      if (k % kFixEvery != 0 || k / kFixEvery >= n_fix) continue;
      FrameResult f;
      f.mode = loop.frameInputs(t).force_lost_in_space || k == 0 ? StarTrackerMode::kLostInSpace
                                                                 : StarTrackerMode::kTracking;
      f.q_ib = q * quatExp(Eigen::LLT<Mat3>(kFixCov).matrixL() * normal3());
      f.cov_body = kFixCov;
      fix_index = k / kFixEvery;
      loop.pushFix(t, uint64_t(k), f);
    }
    loop.flush();
  }
  res.rms_rate_err = rad2deg(std::sqrt(se / std::max<long>(1, n_se)));
  return res;
}

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s / double(v.size());
}

/// Fraction of the (run-averaged, 3 dof) values inside the 95 % band, and its one-sided 99 %
/// lower limit for a consistent filter: from 6 batch means (correlated) or as Bernoulli.
struct BandCheck {
  double fraction = 0, lower = 0, mean = 0;
};
BandCheck check(const std::vector<double>& v, bool batches) {
  const ChiSquareBand band = averagedChiSquareBand(3, kRuns, 0.95);
  BandCheck c;
  c.fraction = fractionInside(v, band);
  c.mean = mean(v);
  if (!batches) {
    c.lower = 0.95 - 2.326 * std::sqrt(0.95 * 0.05 / double(v.size()));
    return c;
  }
  constexpr int kBatches = 6;
  const std::size_t len = v.size() / kBatches;
  std::vector<double> f(kBatches);
  for (int b = 0; b < kBatches; ++b)
    f[b] = fractionInside(std::vector<double>(v.begin() + b * len, v.begin() + (b + 1) * len),
                          band);
  const double m = mean(f);
  double var = 0;
  for (double x : f) var += (x - m) * (x - m) / (kBatches - 1);
  c.lower = 0.95 - 3.365 * std::sqrt(var / kBatches);
  return c;
}

void print(const char* name, const McResult& r, const BandCheck& a, const BandCheck& w,
           const BandCheck& n) {
  std::printf("%s: attitude NEES in band %.1f %% (lower limit %.1f %%, mean %.2f), rate NEES "
              "%.1f %% (%.1f %%, mean %.2f), NIS %.1f %% (%.1f %%, mean %.2f); 3 expected; "
              "rejected %d; max true rate %.2f deg/s; rate error RMS %.5f deg/s\n",
              name, 100 * a.fraction, 100 * a.lower, a.mean, 100 * w.fraction, 100 * w.lower,
              w.mean, 100 * n.fraction, 100 * n.lower, n.mean, r.rejected, r.max_rate_deg_s,
              r.rms_rate_err);
}

TEST(GyrolessMonteCarlo, AttitudeAndRateNeesAndNisInsideChiSquareBands) {
  const McResult r = runMonteCarlo(1.0);
  const BandCheck a = check(r.nees_att, true), w = check(r.nees_rate, true),
                  n = check(r.nis, false);
  print("gyroless, tuned", r, a, w, n);
  EXPECT_GE(a.fraction, a.lower);
  EXPECT_GE(w.fraction, w.lower);
  EXPECT_GE(n.fraction, n.lower);
  // The profile: rates up to about 1 deg/s.
  EXPECT_GT(r.max_rate_deg_s, 0.8);
  EXPECT_LT(r.max_rate_deg_s, 2.5);
}

TEST(GyrolessMonteCarlo, RateWalkHundredTimesTooSmallFailsTheSameCheck) {
  const McResult r = runMonteCarlo(0.01);
  const BandCheck a = check(r.nees_att, true), w = check(r.nees_rate, true),
                  n = check(r.nis, false);
  print("gyroless, rate walk / 100", r, a, w, n);
  EXPECT_LT(a.fraction, a.lower);
  EXPECT_LT(w.fraction, w.lower);
  EXPECT_LT(n.fraction, n.lower);
}

}  // namespace
}  // namespace st
