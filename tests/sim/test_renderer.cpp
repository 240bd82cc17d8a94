// Star renderer: position, photometry and motion blur of noiseless rendered stars.
#include <gtest/gtest.h>

#include <cmath>

#include "common/attitude.hpp"
#include "common/conventions.hpp"
#include "sensors/sim/star_renderer.hpp"

namespace st {
namespace {

struct Moments {
  Vec2 mean;
  Mat2 cov;
  double total;
};

// Intensity-weighted centroid and second moments over the whole image.
Moments moments(const cv::Mat& img) {
  double s = 0, sx = 0, sy = 0;
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x) {
      const double v = img.at<double>(y, x);
      s += v, sx += v * x, sy += v * y;
    }
  Moments m{Vec2(sx / s, sy / s), Mat2::Zero(), s};
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x) {
      const double v = img.at<double>(y, x) / s;
      const Vec2 d(x - m.mean.x(), y - m.mean.y());
      m.cov += v * d * d.transpose();
    }
  return m;
}

struct Scene {
  CameraModel cam;
  SensorParams sensor;
  Quat q_ib;
  // A single star whose true pixel at attitude q_ib is `px`.
  ListStarSource starAt(const Vec2& px, double mag) const {
    const Vec3 u_i = q_ib.toRotationMatrix() * cam.pixelToVector(px);
    return ListStarSource({SkyStar{42, u_i.normalized(), mag}});
  }
};

Scene makeScene(Distortion dist = {}) {
  Scene s;
  const CameraModel base = CameraModel::fromFov(256, 200, deg2rad(10.0));
  s.cam = CameraModel(base.width(), base.height(), base.fx(), base.fy(), base.cx(), base.cy(), dist);
  s.q_ib = attitudeFromRaDecRoll({deg2rad(120.0), deg2rad(-30.0), deg2rad(15.0)});
  return s;
}

TEST(StarRenderer, NoiselessCentroidEqualsProjectedPosition) {
  for (const Distortion& d : {Distortion{}, Distortion{-0.2, 0.05, 1e-3, -5e-4, 0.0}}) {
    const Scene sc = makeScene(d);
    for (const Vec2& px : {Vec2(100.3, 80.7), Vec2(30.55, 170.05), Vec2(200.0, 20.5)}) {
      const ListStarSource src = sc.starAt(px, 5.0);
      const StarRenderer r(sc.cam, sc.sensor, src);
      cv::Mat e(sc.cam.height(), sc.cam.width(), CV_64FC1, cv::Scalar(0));
      const auto truth = r.render(constantRateAttitude(sc.q_ib, Vec3::Zero()), e);
      ASSERT_EQ(truth.size(), 1u);
      // Truth is the projection through the camera model (distortion included).
      const Vec3 v_b = sc.q_ib.toRotationMatrix().transpose() * src.stars()[0].u_i;
      EXPECT_LT((truth[0].px - *sc.cam.vectorToPixel(v_b)).norm(), 1e-9);
      EXPECT_LT((truth[0].px - px).norm(), 1e-6);
      const Moments m = moments(e);
      EXPECT_LT((m.mean - px).norm(), 0.01) << "star at " << px.transpose();
      // Teeth: a star rendered half a pixel off would fail the same check.
      EXPECT_GT((m.mean - (px + Vec2(0.02, 0))).norm(), 0.01);
    }
  }
}

TEST(StarRenderer, TotalElectronsMatchEquation34) {
  const Scene sc = makeScene();
  for (double mag : {2.0, 4.5, 7.0}) {
    const ListStarSource src = sc.starAt(Vec2(128.2, 99.6), mag);
    const StarRenderer r(sc.cam, sc.sensor, src);
    cv::Mat e(sc.cam.height(), sc.cam.width(), CV_64FC1, cv::Scalar(0));
    const auto truth = r.render(constantRateAttitude(sc.q_ib, Vec3::Zero()), e);
    ASSERT_EQ(truth.size(), 1u);
    // Eq. 3.4 recomputed by hand from the documented parameters: F0 10^(-0.4 V) A tau QE t.
    const SensorParams& p = sc.sensor;
    const double area = kPi / 4 * p.aperture_diameter_m * p.aperture_diameter_m;
    const double expected = 8.8e9 * std::pow(10.0, -0.4 * mag) * area * p.transmission * p.qe * p.exposure_s;
    EXPECT_DOUBLE_EQ(p.v0_photon_flux, 8.8e9);
    EXPECT_NEAR(truth[0].electrons / expected, 1.0, 1e-12);
    EXPECT_NEAR(cv::sum(e)[0] / expected, 1.0, 0.01) << "mag " << mag;
    // One magnitude is a factor 10^0.4 = 2.512 in flux.
    EXPECT_NEAR(p.starElectrons(mag) / p.starElectrons(mag + 1), std::pow(10.0, 0.4), 1e-9);
  }
}

TEST(StarRenderer, MotionBlurStreakCentredAtMidExposureWithTheRightLength) {
  const Scene sc = makeScene();
  const Vec2 px(120.4, 101.3);
  const ListStarSource src = sc.starAt(px, 4.0);
  SensorParams sensor = sc.sensor;
  sensor.exposure_s = 0.1;
  const StarRenderer r(sc.cam, sensor, src);
  // 1 deg/s about body y: stars move along x by f * w * T pixels during the exposure.
  const Vec3 w(0, deg2rad(1.0), 0);
  cv::Mat e(sc.cam.height(), sc.cam.width(), CV_64FC1, cv::Scalar(0));
  const auto truth = r.render(constantRateAttitude(sc.q_ib, w), e);
  ASSERT_EQ(truth.size(), 1u);
  EXPECT_LT((truth[0].px - px).norm(), 1e-6);  // truth = mid-exposure position
  const Moments m = moments(e);
  EXPECT_LT((m.mean - px).norm(), 0.01);
  // A uniform streak of length L convolved with the PSF and integrated over unit pixels:
  // variance sigma^2 + 1/12 (the pixel box) + L^2/12 (the streak) along it.
  const double L = sc.cam.fx() * w.norm() * sensor.exposure_s;  // ~2.5 px near the centre
  const double s2 = sensor.psf_sigma_px * sensor.psf_sigma_px + 1.0 / 12.0;
  EXPECT_NEAR(m.cov(0, 0), s2 + L * L / 12.0, 0.01 * (s2 + L * L / 12.0));
  EXPECT_NEAR(m.cov(1, 1), s2, 0.01 * s2);
  EXPECT_GE(r.lastSubsteps(), static_cast<int>(L / (0.5 * sensor.psf_sigma_px)));
  EXPECT_NEAR(m.total / sensor.starElectrons(4.0), 1.0, 0.01);
  // Teeth: the start-of-exposure position is half a streak away from the centroid.
  const Vec3 v_start = (sc.q_ib * quatExp(-0.05 * w)).toRotationMatrix().transpose() * src.stars()[0].u_i;
  EXPECT_GT((m.mean - *sc.cam.vectorToPixel(v_start)).norm(), 1.0);
}

TEST(StarRenderer, SmoothStreakHasNoSubstepRipple) {
  // Along a long streak, the profile must be flat (no bumps at the sub-step positions).
  const Scene sc = makeScene();
  const Vec2 px(128.0, 100.0);
  const ListStarSource src = sc.starAt(px, 3.0);
  SensorParams sensor = sc.sensor;
  sensor.psf_sigma_px = 0.6;
  const StarRenderer r(sc.cam, sensor, src);
  const Vec3 w(0, deg2rad(20.0), 0);  // ~50 px streak
  cv::Mat e(sc.cam.height(), sc.cam.width(), CV_64FC1, cv::Scalar(0));
  r.render(constantRateAttitude(sc.q_ib, w), e);
  // Column sums in the middle third of the streak are equal to 0.5 % (only the tan()
  // stretch of the projection varies slowly across it).
  double lo = 1e300, hi = 0;
  for (int x = 118; x <= 138; ++x) {
    const double c = cv::sum(e.col(x))[0];
    lo = std::min(lo, c), hi = std::max(hi, c);
  }
  EXPECT_LT(hi / lo - 1.0, 0.005);
  // The default sub-step spacing against a 5x finer one (close to the continuous streak):
  // the difference (midpoint-rule error at the streak ends) must stay below the shot noise
  // of the brightest unsaturated pixel, i.e. relative to the peak < 1 / sqrt(full well).
  RenderOptions fine;
  fine.max_substep_sigma = 0.1;
  cv::Mat e_fine(sc.cam.height(), sc.cam.width(), CV_64FC1, cv::Scalar(0));
  r.render(constantRateAttitude(sc.q_ib, w), e_fine, fine);
  double peak = 0;
  cv::minMaxLoc(e, nullptr, &peak);
  EXPECT_LT(cv::norm(e, e_fine, cv::NORM_INF) / peak, 1.0 / std::sqrt(sensor.full_well_e));
  // Teeth: one PSF per 3 sigma is visibly lumpy.
  RenderOptions coarse;
  coarse.max_substep_sigma = 3.0;
  cv::Mat e_coarse(sc.cam.height(), sc.cam.width(), CV_64FC1, cv::Scalar(0));
  r.render(constantRateAttitude(sc.q_ib, w), e_coarse, coarse);
  EXPECT_GT(cv::norm(e_coarse, e_fine, cv::NORM_INF) / peak, 1.0 / std::sqrt(sensor.full_well_e));
}

TEST(StarRenderer, StarsOutsideTheFieldAreNotInTheTruth) {
  const Scene sc = makeScene();
  std::vector<SkyStar> stars;
  const Mat3 R = sc.q_ib.toRotationMatrix();
  stars.push_back({1, (R * sc.cam.pixelToVector({50, 50})).normalized(), 5.0});
  stars.push_back({2, (R * sc.cam.pixelToVector({-20, 50})).normalized(), 5.0});   // left
  stars.push_back({3, (R * sc.cam.pixelToVector({-0.3, 60})).normalized(), 5.0});  // edge, in
  stars.push_back({4, (R * Vec3(0, 0, -1)).normalized(), 5.0});                     // behind
  const ListStarSource src(stars);
  const StarRenderer r(sc.cam, sc.sensor, src);
  cv::Mat e(sc.cam.height(), sc.cam.width(), CV_64FC1, cv::Scalar(0));
  const auto truth = r.render(constantRateAttitude(sc.q_ib, Vec3::Zero()), e);
  ASSERT_EQ(truth.size(), 2u);
  EXPECT_TRUE((truth[0].id == 1 && truth[1].id == 3) || (truth[0].id == 3 && truth[1].id == 1));
}

TEST(StarRenderer, MissingStarsAreAStableFraction) {
  RenderOptions o;
  o.missing_star_fraction = 0.2;
  o.missing_star_seed = 7;
  int missing = 0;
  const int n = 20000;
  for (uint32_t id = 1; id <= n; ++id) missing += StarRenderer::isMissing(id, o);
  // Binomial(20000, 0.2): sd = 57; 5 sd bound.
  EXPECT_NEAR(missing, 0.2 * n, 5 * std::sqrt(n * 0.2 * 0.8));
  o.missing_star_fraction = 0;
  EXPECT_FALSE(StarRenderer::isMissing(1, o));
}

}  // namespace
}  // namespace st
