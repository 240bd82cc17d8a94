// Monte Carlo consistency of the MEKF (issue 8 acceptance; Bar-Shalom et al. sec. 5.4):
// Every run goes through the one fusion loop (fusion/fusion_loop.hpp) that replay and live use,
// with synthetic fixes in place of the tracker.
// 50 runs of 180 s of jittering slew, gyro at 50 Hz from GyroSimulator, star-tracker fixes at
// 5 Hz synthesised as truth perturbed by their covariance, a scripted 30 s outage.
//  - run-averaged 6-state NEES inside the two-sided 95 % chi-square band for >= 95 % of steps,
//    run-averaged NIS of the fixes likewise;
//  - the same filter with its process noise mistuned by 10x (Q*10 and Q/10) fails that test;
//  - bias within 3 sigma at 60 s, filter error below the raw fixes, outage inside 3 sigma;
//  - the same with tight coupling (2-4 star vectors per frame instead of a fix).
//
// About ">= 95 % of steps inside the 95 % band": for an exactly consistent filter the EXPECTED
// fraction is 95 %, so the literal criterion is a coin flip. Over 40 disjoint seed sets
// (ST_MC_SEED = 0, 50, ..., 1950; 2,000 runs per mode) this filter gave, with fixes: NEES
// 73.7-99.1 % (mean 94.4, >= 95 % in 26 of 40), NIS 93.2-96.9 % (mean 95.0, 21 of 40); with
// star vectors: NEES 72.9-98.9 % (mean 94.4, 25 of 40), NIS 93.5-96.4 % (mean 94.9, 18 of
// 40); the mean NEES of a set 5.37-6.54 (6 expected). The test therefore asserts the
// one-sided 99 % lower confidence limit of that fraction under a consistent filter, derived
// from its sampling distribution, and prints the literal fraction (1 of the 80 nominal
// evaluations above fell under its limit, by 0.1 %: 0.8 expected):
//  - NIS: innovations of a consistent filter are white, so the per-update indicators are
//    independent Bernoulli(0.95): bound = 0.95 - 2.326 sqrt(0.95 * 0.05 / n_updates);
//  - NEES: the averaged NEES wanders slowly (the bias error decorrelates over tens of
//    seconds), so the fraction's variance comes from 6 batch means of 30 s each:
//    bound = 0.95 - t(0.99, 5) s_batch / sqrt(6), t(0.99, 5) = 3.365.
// The mistuned filters land at <= 1.5 % over the same 40 sets and fail by a wide margin.
// Env: ST_MC_SEED=<offset> reruns with other seeds (run r hashes 1000 + r + offset and
// 5000 + r + offset: offsets 50 apart give disjoint sets); ST_MC_DEBUG=1 prints NEES and NIS
// per 10 s.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cstdlib>
#include <map>
#include <random>

#include "common/attitude.hpp"
#include "common/conventions.hpp"
#include "fusion/consistency.hpp"
#include "fusion/mekf.hpp"
#include "fusion/fusion_loop.hpp"
#include "sensors/sim/gyro_model.hpp"
#include "sensors/sim/motion.hpp"
#include "sensors/sim/random_streams.hpp"

namespace st {
namespace {

constexpr int kRuns = 50;
constexpr double kDuration = 180;  // [s]
constexpr double kGyroDt = 0.02;   // 50 Hz
constexpr int kFixEvery = 10;      // 5 Hz
constexpr double kOutageStart = 100, kOutageEnd = 130;
constexpr int kSteps = static_cast<int>(kDuration / kGyroDt + 0.5);

/// The truth tabulated on the gyro grid: every run samples the same times, so the jitter
/// profile is integrated once instead of once per run.
class GridMotion : public MotionProfile {
 public:
  explicit GridMotion(const MotionProfile& m) : m_(m) {
    for (int k = 0; k <= kSteps; ++k) q_.push_back(m.attitude(k * kGyroDt));
  }
  Quat attitude(double t) const override {
    const long k = std::lround(t / kGyroDt);
    if (k >= 0 && k < static_cast<long>(q_.size()) && std::abs(t - k * kGyroDt) < 1e-9)
      return q_[k];
    return m_.attitude(t);
  }
  Vec3 rateBody(double t) const override { return m_.rateBody(t); }
  std::string type() const override { return m_.type(); }

 private:
  const MotionProfile& m_;
  std::vector<Quat> q_;
};

const GridMotion& truthMotion() {
  static const JitterMotion jitter(
      attitudeFromRaDecRoll({deg2rad(80.0), deg2rad(-30.0), deg2rad(15.0)}),
      deg2rad(1.0) * Vec3(0.1, 0.3, -0.2), deg2rad(1.0) * Vec3(0.05, 0.08, 0.1),
      Vec3(0.2, 0.5, 1.1), Vec3(0.0, 1.0, 2.0), 2e-3);
  static const GridMotion grid(jitter);
  return grid;
}

GyroParams gyroParams() {
  GyroParams p{};
  p.rate_hz = 1.0 / kGyroDt;
  p.arw_deg_rt_h = 0.3;
  p.rrw_deg_h_rt_h = 3.0;
  p.bias_deg_h = 0;  // the turn-on bias is drawn per run from the filter's prior
  return p;
}
constexpr double kBiasSigmaDegH = 20;
const Mat3 kFixCov =
    Vec3(std::pow(arcsec2rad(5), 2), std::pow(arcsec2rad(5), 2), std::pow(arcsec2rad(40), 2))
        .asDiagonal();
constexpr double kStarSigma = 5.0 / 206264.80624709636;  // 5 arcsec
constexpr double kInitialAttitudeSigma = 1e-3;           // [rad]

enum class Mode { kFixes, kStarVectors };

struct McResult {
  std::vector<double> nees;  ///< run-averaged 6-state NEES per gyro step
  std::vector<double> nis;   ///< run-averaged NIS per update time
  std::vector<int> nis_dof;  ///< its degrees of freedom (per run)
  int rejected = 0, rejected_after_outage = 0, reinits = 0;
  double bias_inside_3sigma_at_60 = 0;  ///< fraction of run-axes
  double bias_sigma_ratio_at_60 = 0;    ///< mean sigma_b(60) / sigma_b(0)
  double rms_filter = 0, rms_fix = 0;   ///< total attitude error at update times [rad]
  double outage_inside_3sigma = 0;      ///< fraction of run-step-axes inside 3 sigma
  double sigma_growth = 0;              ///< min over runs of trace P_att(130) / trace(100)
};

/// One run's fix at t1: the truth perturbed by the fix covariance, or 2-4 star vectors
/// (within ~8 deg of the boresight, noise across the line of sight) as a FrameResult whose
/// covariance is their QUEST covariance, so that the loop's per-star sigma is kStarSigma.
/// `lis`: the loop asked for lost-in-space (a re-initialisation is pending).
FrameResult makeFix(Mode mode, const Quat& q_true, bool lis, int update_index,
                    std::mt19937_64& rng, std::map<uint32_t, Vec3>& catalog) {
  std::normal_distribution<double> n01;
  auto normal3 = [&] { return Vec3(n01(rng), n01(rng), n01(rng)); };
  FrameResult f;
  f.mode = lis ? StarTrackerMode::kLostInSpace : StarTrackerMode::kTracking;
  if (mode == Mode::kFixes) {
    f.q_ib = q_true * quatExp(Eigen::LLT<Mat3>(kFixCov).matrixL() * normal3());
    f.cov_body = kFixCov;
    return f;
  }
  std::uniform_real_distribution<double> uni(-0.14, 0.14);
  const int n_stars = 2 + (update_index % 3);
  Mat3 info = Mat3::Zero();
  for (int s = 0; s < n_stars; ++s) {
    const Vec3 b_true = Vec3(uni(rng), uni(rng), 1.0).normalized();
    Vec3 noise = normal3() * kStarSigma;
    noise -= b_true * b_true.dot(noise);
    MatchedStar m;
    m.catalog_id = static_cast<uint32_t>(4 * update_index + s);
    m.v_cam = (b_true + noise).normalized();
    catalog[m.catalog_id] = q_true * b_true;
    f.stars.push_back(m);
    info += (Mat3::Identity() - b_true * b_true.transpose()) / (kStarSigma * kStarSigma);
  }
  f.q_ib = q_true;  // unused by a star-vector update
  f.cov_body = info.inverse();
  return f;
}

McResult runMonteCarlo(Mode mode, double q_scale) {
  const GridMotion& truth = truthMotion();
  const GyroParams gp = gyroParams();
  FusionOptions fo;
  fo.filter = MekfOptions::fromDatasheet(gp.arw_deg_rt_h, gp.rrw_deg_h_rt_h, kBiasSigmaDegH);
  fo.filter.arw_rad_rt_s *= std::sqrt(q_scale);  // Q scales with the squares
  fo.filter.rrw_rad_s_rt_s *= std::sqrt(q_scale);
  fo.update = mode == Mode::kFixes ? FusionOptions::Update::kAttitude
                                   : FusionOptions::Update::kStarVectors;
  fo.reorder_window_s = 0;  // events are pushed in time order
  McResult res;
  res.nees.assign(kSteps, 0.0);
  std::vector<double> nis_sum;
  std::vector<int> nis_count;
  double se_filter = 0, se_fix = 0, bias_in = 0, sigma_ratio = 0, outage_in = 0;
  int n_err = 0, n_outage = 0;
  res.sigma_growth = 1e300;
  for (int run = 0; run < kRuns; ++run) {
    const int off = std::getenv("ST_MC_SEED") ? std::atoi(std::getenv("ST_MC_SEED")) : 0;
    // Hashed seeds: with std::mt19937_64 seeded by consecutive integers (1000 + run, and
    // 5000 + run for the gyro) the run-averaged NIS had 4.2 +- 0.8 % more variance than
    // chi2(150)/50 over 40 seed sets (runs slightly dependent), 0.0 +- 0.8 % once hashed.
    std::mt19937_64 rng(splitMix64(1000 + run + off));
    std::normal_distribution<double> n01;
    auto normal3 = [&] { return Vec3(n01(rng), n01(rng), n01(rng)); };
    // The turn-on bias is drawn from the filter's (well-tuned) prior.
    const Vec3 bias0 = normal3() * deg2rad(kBiasSigmaDegH) / 3600.0;
    GyroSimulator gyro(gp, splitMix64(5000 + run + off), bias0);
    // The one fusion loop of replay and live, fed with synthetic fixes instead of a tracker.
    std::map<uint32_t, Vec3> catalog;
    FusionLoop loop(fo, [&catalog](uint32_t id) -> std::optional<Vec3> {
      const auto it = catalog.find(id);
      return it == catalog.end() ? std::nullopt : std::optional<Vec3>(it->second);
    });
    int update_index = 0;
    bool first_after_outage = true;
    double trace_at_outage = 0;
    Quat q_fix = Quat::Identity();
    loop.setStepCallback([&](const FusionStep& s) {
      if (s.use != FixUse::kAccepted && s.use != FixUse::kRejected) return;
      // The NIS is a statistic of the innovation whether or not the gate then accepts it.
      // Every run has the same number of stars at the same update index, so the dof match.
      if (nis_sum.size() <= std::size_t(update_index)) {
        nis_sum.resize(update_index + 1, 0.0);
        nis_count.resize(update_index + 1, 0);
        res.nis_dof.resize(update_index + 1, s.update.dof);
      }
      nis_sum[update_index] += s.update.nis;
      ++nis_count[update_index];
      if (s.use == FixUse::kRejected) {
        ++res.rejected;
        if (s.t > kOutageEnd && first_after_outage) ++res.rejected_after_outage;
      }
    });
    // The first fix initialises the filter (a lost-in-space fix of 1 mrad per axis).
    const Vec3 e0 = normal3() * kInitialAttitudeSigma;
    FrameResult init;
    init.mode = StarTrackerMode::kLostInSpace;
    init.q_ib = truth.attitude(0) * quatExp(-e0);
    init.cov_body = Mat3::Identity() * kInitialAttitudeSigma * kInitialAttitudeSigma;
    loop.pushFix(0, 0, init);
    for (int k = 0; k < kSteps; ++k) {
      const double t0 = k * kGyroDt, t1 = (k + 1) * kGyroDt;
      loop.pushGyro(t1, gyro.sample(truth, t0, t1));
      const AttitudeMekf& f = loop.filter();
      const Quat q_true = truth.attitude(t1);
      const bool in_outage = t1 > kOutageStart && t1 <= kOutageEnd;
      if (std::abs(t1 - kOutageStart) < 1e-9) trace_at_outage = f.attitudeCov().trace();
      if ((k + 1) % kFixEvery == 0 && !in_outage) {
        const bool lis = loop.frameInputs(t1).force_lost_in_space;
        const FrameResult fix = makeFix(mode, q_true, lis, update_index, rng, catalog);
        q_fix = fix.q_ib;
        loop.pushFix(t1, uint64_t(k + 1), fix);
        if (t1 > kOutageEnd) first_after_outage = false;
        if (t1 > 10) {
          se_filter += std::pow(attitudeError(f.attitude(), q_true).total, 2);
          se_fix += std::pow(attitudeError(q_fix, q_true).total, 2);
          ++n_err;
        }
        ++update_index;
      }
      // 6-state NEES against the truth.
      Vec6 e;
      e << attitudeError(f.attitude(), q_true).rotvec_body, gyro.bias() - f.bias();
      res.nees[k] += e.dot(f.covariance().ldlt().solve(e)) / kRuns;
      if (std::abs(t1 - 60) < 1e-9) {
        for (int a = 0; a < 3; ++a)
          bias_in += std::abs(e[3 + a]) <= 3 * std::sqrt(f.covariance()(3 + a, 3 + a)) ? 1 : 0;
        sigma_ratio +=
            std::sqrt(f.covariance()(3, 3)) / fo.filter.initial_bias_sigma_rad_s / kRuns;
      }
      if (in_outage) {
        for (int a = 0; a < 3; ++a) {
          outage_in += std::abs(e[a]) <= 3 * std::sqrt(f.covariance()(a, a)) ? 1 : 0;
          ++n_outage;
        }
      }
      if (std::abs(t1 - kOutageEnd) < 1e-9)
        res.sigma_growth = std::min(res.sigma_growth, f.attitudeCov().trace() / trace_at_outage);
    }
    loop.flush();
    res.reinits += loop.reinitializations();
  }
  for (std::size_t i = 0; i < nis_sum.size(); ++i) res.nis.push_back(nis_sum[i] / nis_count[i]);
  res.bias_inside_3sigma_at_60 = bias_in / (3.0 * kRuns);
  res.bias_sigma_ratio_at_60 = sigma_ratio;
  res.rms_filter = std::sqrt(se_filter / n_err);
  res.rms_fix = std::sqrt(se_fix / n_err);
  res.outage_inside_3sigma = outage_in / n_outage;
  return res;
}

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s / v.size();
}

double neesFraction(const McResult& r) {
  return fractionInside(r.nees, averagedChiSquareBand(6, kRuns, 0.95));
}

double nisFraction(const McResult& r) {
  int inside = 0;
  for (std::size_t i = 0; i < r.nis.size(); ++i)
    inside += averagedChiSquareBand(r.nis_dof[i], kRuns, 0.95).contains(r.nis[i]) ? 1 : 0;
  return r.nis.empty() ? 0.0 : static_cast<double>(inside) / r.nis.size();
}

double nisLowerBound(const McResult& r) {
  return 0.95 - 2.326 * std::sqrt(0.95 * 0.05 / r.nis.size());
}

double neesLowerBound(const McResult& r) {
  const ChiSquareBand band = averagedChiSquareBand(6, kRuns, 0.95);
  constexpr int kBatches = 6;
  const std::size_t len = r.nees.size() / kBatches;
  std::vector<double> f(kBatches);
  for (int b = 0; b < kBatches; ++b)
    f[b] = fractionInside(
        std::vector<double>(r.nees.begin() + b * len, r.nees.begin() + (b + 1) * len), band);
  const double m = mean(f);
  double var = 0;
  for (double x : f) var += (x - m) * (x - m) / (kBatches - 1);
  return 0.95 - 3.365 * std::sqrt(var / kBatches);
}

void print(const char* name, const McResult& r) {
  if (std::getenv("ST_MC_DEBUG")) {
    const ChiSquareBand b = averagedChiSquareBand(6, kRuns, 0.95);
    for (int seg = 0; seg < 18; ++seg) {
      int above = 0, below = 0;
      double m = 0;
      for (int k = seg * 500; k < (seg + 1) * 500; ++k) {
        above += r.nees[k] > b.hi;
        below += r.nees[k] < b.lo;
        m += r.nees[k] / 500;
      }
      if (seg == 0) {
        double m2 = 0, mm = mean(r.nis);
        int ab = 0, be = 0;
        const ChiSquareBand bn = averagedChiSquareBand(r.nis_dof[0], kRuns, 0.95);
        for (double x : r.nis) {
          m2 += (x - mm) * (x - mm) / r.nis.size();
          ab += x > bn.hi;
          be += x < bn.lo;
        }
        std::printf("  NIS var %.4f (theory %.4f), above %d below %d\n", m2,
                    2.0 * r.nis_dof[0] / kRuns, ab, be);
      }
      double nis_m = 0;  // the 50 updates of this 10 s (5 Hz)
      int nis_n = 0;
      for (std::size_t i = seg * 50u; i < r.nis.size() && i < (seg + 1) * 50u; ++i, ++nis_n)
        nis_m += r.nis[i];
      std::printf("  t %3d-%3d s: mean NEES %.2f, above %d, below %d; mean NIS %.3f\n", seg * 10,
                  seg * 10 + 10, m, above, below, nis_n ? nis_m / nis_n : 0.0);
    }
  }
  std::printf(
      "%s: NEES in band %.1f %% of %zu steps (mean %.2f, 6 expected), NIS in band %.1f %% of "
      "%zu updates (mean %.2f), rejected %d, re-initialised %d; 99 %% lower limits NEES %.1f %%, "
      "NIS %.1f %%\n",
      name, 100 * neesFraction(r), r.nees.size(), mean(r.nees), 100 * nisFraction(r), r.nis.size(),
      mean(r.nis), r.rejected, r.reinits, 100 * neesLowerBound(r), 100 * nisLowerBound(r));
}

bool passesConsistency(const McResult& r) {
  return neesFraction(r) >= neesLowerBound(r) && nisFraction(r) >= nisLowerBound(r);
}

TEST(MekfMonteCarlo, AttitudeFixesConsistentAndMistunedFilterFails) {
  const McResult r = runMonteCarlo(Mode::kFixes, 1.0);
  print("fixes, nominal Q", r);
  std::printf(
      "  bias at 60 s: %.1f %% of run-axes within 3 sigma, sigma_b(60)/sigma_b(0) = %.3f\n"
      "  RMS attitude error (t > 10 s): filter %.2f arcsec, raw fixes %.2f arcsec\n"
      "  30 s outage: %.2f %% of run-step-axes within 3 sigma, min P growth x%.1f, "
      "first fix after it rejected in %d runs\n",
      100 * r.bias_inside_3sigma_at_60, r.bias_sigma_ratio_at_60, rad2arcsec(r.rms_filter),
      rad2arcsec(r.rms_fix), 100 * r.outage_inside_3sigma, r.sigma_growth, r.rejected_after_outage);
  EXPECT_GE(neesFraction(r), neesLowerBound(r));
  EXPECT_GE(nisFraction(r), nisLowerBound(r));
  // Bias: per run-axis |error| <= 3 sigma holds with p = 0.9973; allow 2 of 150 misses
  // (binomial P(>2 misses) ~ 1 %), and sigma must have shrunk (converged, not just wide).
  EXPECT_GE(r.bias_inside_3sigma_at_60, 1.0 - 2.0 / 150);
  EXPECT_LT(r.bias_sigma_ratio_at_60, 0.2);
  EXPECT_LT(r.rms_filter, r.rms_fix);
  EXPECT_GE(r.outage_inside_3sigma, 0.99);
  EXPECT_GT(r.sigma_growth, 2.0);
  EXPECT_LE(r.rejected_after_outage, 1);  // p(reject) = 0.1 % per run at a 99.9 % gate

  // Teeth: the same test must fail with the process noise mistuned by 10x either way.
  const McResult hi = runMonteCarlo(Mode::kFixes, 10.0);
  print("fixes, Q x 10 ", hi);
  EXPECT_FALSE(passesConsistency(hi));
  const McResult lo = runMonteCarlo(Mode::kFixes, 0.1);
  print("fixes, Q / 10 ", lo);
  EXPECT_FALSE(passesConsistency(lo));
}

TEST(MekfMonteCarlo, StarVectorsConsistentAndMistunedFilterFails) {
  const McResult r = runMonteCarlo(Mode::kStarVectors, 1.0);
  print("stars, nominal Q", r);
  std::printf("  bias at 60 s within 3 sigma: %.1f %%, outage within 3 sigma: %.2f %%\n",
              100 * r.bias_inside_3sigma_at_60, 100 * r.outage_inside_3sigma);
  EXPECT_GE(neesFraction(r), neesLowerBound(r));
  EXPECT_GE(nisFraction(r), nisLowerBound(r));
  EXPECT_GE(r.bias_inside_3sigma_at_60, 1.0 - 2.0 / 150);
  EXPECT_GE(r.outage_inside_3sigma, 0.99);
  const McResult hi = runMonteCarlo(Mode::kStarVectors, 10.0);
  print("stars, Q x 10 ", hi);
  EXPECT_FALSE(passesConsistency(hi));
}

}  // namespace
}  // namespace st
