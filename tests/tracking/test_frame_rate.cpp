// The body rate from two frames' common stars (sensors/tracking/frame_rate.hpp; seed 004 eq.
// 7.1): exact without noise, unbiased and consistent with its covariance under star noise,
// in the body frame of a mounted camera, and carried by the tracker's FrameResult from the
// second solved frame of a simulated slew.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <cstdlib>
#include <random>

#include "common/chi_square.hpp"
#include "common/conventions.hpp"
#include "sensors/tracking/frame_rate.hpp"
#include "sensors/tracking/star_tracker.hpp"
#include "tests/tracking/tracker_sim.hpp"

namespace st {
namespace {

/// Two frames dt apart of n stars within ~8 deg of the boresight, the body turning at w_cam,
/// each vector with noise sigma across its line of sight; star ids 1..n.
std::pair<RateFrame, RateFrame> twoFrames(const Vec3& w_cam, double dt, int n, double sigma,
                                          std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-0.14, 0.14);
  std::normal_distribution<double> n01;
  auto noisy = [&](const Vec3& v) {
    Vec3 e(n01(rng), n01(rng), n01(rng));
    e = (e - v * v.dot(e)) * sigma;
    return Vec3((v + e).normalized());
  };
  const Mat3 A12 = quatExp(w_cam * dt).toRotationMatrix();  // v1 = A12 v2
  RateFrame a, b;
  a.t_s = 10.0;
  b.t_s = 10.0 + dt;
  a.sigma = b.sigma = sigma;
  for (int k = 0; k < n; ++k) {
    const Vec3 v2 = Vec3(u(rng), u(rng), 1.0).normalized();
    const Vec3 v1 = A12 * v2;
    a.ids.push_back(k + 1);
    b.ids.push_back(k + 1);
    a.v_cam.push_back(noisy(v1));
    b.v_cam.push_back(noisy(v2));
  }
  return {a, b};
}

TEST(FrameRate, ExactWithoutNoiseAndInTheBodyFrame) {
  std::mt19937_64 rng(1);
  const Vec3 w(deg2rad(0.7), deg2rad(-0.4), deg2rad(1.5));
  auto [a, b] = twoFrames(w, 0.2, 8, 1e-12, rng);
  a.sigma = b.sigma = arcsec2rad(5);
  const auto r = measureFrameRate(a, b, Mat3::Identity());
  ASSERT_TRUE(r);
  EXPECT_LT((r->rate_body - w).norm(), 1e-9);
  EXPECT_EQ(r->stars, 8);
  EXPECT_NEAR(r->interval_s, 0.2, 1e-12);
  // A camera mounted 90 deg about x: the rate in the body frame is R_bc w_cam.
  const Mat3 R_bc = quatExp(Vec3(M_PI / 2, 0, 0)).toRotationMatrix();
  const auto rb = measureFrameRate(a, b, R_bc);
  ASSERT_TRUE(rb);
  EXPECT_LT((rb->rate_body - R_bc * w).norm(), 1e-9);
  EXPECT_LT((rb->cov_body - R_bc * r->cov_body * R_bc.transpose()).norm(),
            1e-9 * r->cov_body.norm());
}

TEST(FrameRate, NeedsTwoCommonStarsAndAPositiveInterval) {
  std::mt19937_64 rng(2);
  auto [a, b] = twoFrames(Vec3(0.01, 0, 0), 0.1, 5, arcsec2rad(5), rng);
  RateFrame one = b;
  for (uint32_t& id : one.ids) id += 100;  // no common star ...
  one.ids[0] = a.ids[0];                   // ... but one
  EXPECT_FALSE(measureFrameRate(a, one, Mat3::Identity()));
  RateFrame same_time = b;
  same_time.t_s = a.t_s;
  EXPECT_FALSE(measureFrameRate(a, same_time, Mat3::Identity()));
  EXPECT_TRUE(measureFrameRate(a, b, Mat3::Identity()));
}

// 2000 noisy pairs of 3-12 stars: the rate NEES (3 dof) averages 3 within the 99 % band of
// 2000 chi2(3) draws, and the mean error is zero within 4 standard errors per axis.
TEST(FrameRate, ConsistentWithItsCovariance) {
  std::mt19937_64 rng(3);
  const Vec3 w(deg2rad(0.5), deg2rad(1.0), deg2rad(-0.8));
  const double sigma = arcsec2rad(6);
  constexpr int kTrials = 2000;
  double nees = 0;
  Vec3 mean_err = Vec3::Zero(), var = Vec3::Zero();
  for (int k = 0; k < kTrials; ++k) {
    auto [a, b] = twoFrames(w, 0.1, 3 + k % 10, sigma, rng);
    const auto r = measureFrameRate(a, b, Mat3::Identity());
    ASSERT_TRUE(r);
    const Vec3 e = r->rate_body - w;
    nees += e.dot(r->cov_body.ldlt().solve(e)) / kTrials;
    mean_err += e / kTrials;
    var += r->cov_body.diagonal() / kTrials;
  }
  const double lo = chiSquareQuantile(0.005, 3.0 * kTrials) / kTrials;
  const double hi = chiSquareQuantile(0.995, 3.0 * kTrials) / kTrials;
  std::printf("frame rate: mean NEES %.3f (99 %% band [%.3f, %.3f])\n", nees, lo, hi);
  EXPECT_GT(nees, lo);
  EXPECT_LT(nees, hi);
  for (int i = 0; i < 3; ++i) EXPECT_LT(std::abs(mean_err[i]), 4 * std::sqrt(var[i] / kTrials));
}

// The tracker's own rate on a simulated 1 deg/s slew (rate-match tracking, as without any
// gyro or filter): none on the first frame, then every solved frame carries the mean rate of
// the last interval (exact for a constant rate). Its error against the true rate: RMS
// printed; bounded by its own covariance (theory: frame_rate.hpp) as at least 90 % of frames
// with a NEES below the chi2(3) 99 % point.
TEST(FrameRate, TrackerCarriesTheRateFromTheSecondFrame) {
  const SlewMotion motion(attitudeFromRaDecRoll({deg2rad(84.0), deg2rad(-2.0), 0.0}),
                          Vec3(deg2rad(0.8), deg2rad(-0.5), deg2rad(0.3)));
  test::FrameSimulator sim(116);
  StarTracker pipe(test::simDatabase(), test::simCamera(), test::simTrackerOptions());
  int with_rate = 0, below = 0;
  double se = 0;
  const double q99 = chiSquareQuantile(0.99, 3.0);
  constexpr int kFrames = 30;
  for (int k = 0; k < kFrames; ++k) {
    const auto f = sim.frame(motion, 0.1 * k);
    const FrameResult o = pipe.process(f.image, f.t_s);
    ASSERT_TRUE(o.hasAttitude()) << k << ": " << o.detail;
    if (k == 0) {
      EXPECT_FALSE(o.rate);
      continue;
    }
    ASSERT_TRUE(o.rate) << k;
    ++with_rate;
    EXPECT_GE(o.rate->stars, 3);
    EXPECT_NEAR(o.rate->interval_s, 0.1, 1e-9);
    const Vec3 e = o.rate->rate_body - f.rate_body;
    se += e.squaredNorm();
    if (std::getenv("ST_DEBUG"))
      std::printf("k %d mode %d stars %d e %.5f %.5f %.5f deg/s sigma %.5f %.5f %.5f\n", k,
                  int(o.mode), o.rate->stars, rad2deg(e.x()), rad2deg(e.y()), rad2deg(e.z()),
                  rad2deg(std::sqrt(o.rate->cov_body(0, 0))),
                  rad2deg(std::sqrt(o.rate->cov_body(1, 1))),
                  rad2deg(std::sqrt(o.rate->cov_body(2, 2))));
    below += e.dot(o.rate->cov_body.ldlt().solve(e)) <= q99;
  }
  const double rms = std::sqrt(se / with_rate);
  std::printf("tracker frame rate on a 1 deg/s slew: error RMS %.5f deg/s, %d of %d frames "
              "with NEES below the chi2(3) 99 %% point\n",
              rad2deg(rms), below, with_rate);
  EXPECT_EQ(with_rate, kFrames - 1);
  EXPECT_GE(below, 0.9 * with_rate);
}

}  // namespace
}  // namespace st
