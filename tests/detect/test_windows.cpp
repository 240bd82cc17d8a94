// Predictive centroiding (seed 004 §4.2.3): one result per predicted star, found near the
// truth, with the reasons for misses, reading nothing outside the windows.
#include <gtest/gtest.h>

#include "sensors/detect/star_detector.hpp"
#include "tests/detect/sim_frame.hpp"

namespace st {
namespace {

struct Scene {
  cv::Mat img;
  std::vector<test::SimStar> stars;
  std::vector<PredictedStar> pred;
};

Scene makeScene(uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> n(0, 1);
  Scene s;
  for (int k = 0; k < 20; ++k) {
    const Vec2 p(30 + 40 * (k % 5) + 5 * u(rng), 30 + 40 * (k / 5) + 5 * u(rng));
    s.stars.push_back({p, 6000});
    PredictedStar ps;
    ps.cov_px = Mat2::Identity() * 1.0;  // 1 px prediction sigma
    ps.px = p + Vec2(n(rng), n(rng));
    s.pred.push_back(ps);
  }
  s.img = test::renderFrame(240, 200, s.stars, test::SimCamera{}, rng);
  return s;
}

TEST(Windows, FindsPredictedStarsAndSaysWhyNot) {
  Scene s = makeScene(11);
  s.pred.push_back({Vec2(-20, 50), Mat2::Identity(), Vec2::Zero()});  // off the frame
  s.pred.push_back({Vec2(215, 185), Mat2::Identity(), Vec2::Zero()});  // empty sky
  const auto res = centroidWindows(s.img, s.pred);
  ASSERT_EQ(res.size(), s.pred.size());
  for (std::size_t k = 0; k < s.stars.size(); ++k) {
    ASSERT_TRUE(res[k].centroid.has_value()) << k << ": " << res[k].reason;
    const Vec2 e = res[k].centroid->px - s.stars[k].px;
    // 5 sigma of the reported covariance
    EXPECT_LT(e.dot(res[k].centroid->cov_px.inverse() * e), 25.0) << k;
    EXPECT_LT(e.norm(), 0.2) << k;
  }
  EXPECT_EQ(res[20].reason, "outside image");
  EXPECT_EQ(res[21].reason, "below threshold");
}

TEST(Windows, TouchesOnlyTheWindows) {
  Scene s = makeScene(12);
  const auto a = centroidWindows(s.img, s.pred);
  // Garbage everywhere outside the windows must not change anything.
  cv::Mat keep = cv::Mat::zeros(s.img.size(), CV_8U);
  DetectorOptions o;
  for (const auto& p : s.pred) {
    const int h = windowHalfSize(p, o);
    const cv::Rect r(static_cast<int>(std::lround(p.px.x())) - h,
                     static_cast<int>(std::lround(p.px.y())) - h, 2 * h + 1, 2 * h + 1);
    keep(r & cv::Rect(0, 0, s.img.cols, s.img.rows)).setTo(255);
  }
  cv::Mat garbage(s.img.size(), CV_16U);
  cv::randu(garbage, 0, 65535);
  garbage.copyTo(s.img, ~keep);
  const auto b = centroidWindows(s.img, s.pred);
  for (std::size_t k = 0; k < a.size(); ++k) {
    ASSERT_EQ(a[k].centroid.has_value(), b[k].centroid.has_value());
    if (a[k].centroid) {
      EXPECT_EQ(a[k].centroid->px, b[k].centroid->px);
    }
  }
}

TEST(Windows, SizeGrowsWithUncertaintyAndBlur) {
  DetectorOptions o;
  PredictedStar p;
  p.cov_px = Mat2::Identity() * 0.01;
  const int small = windowHalfSize(p, o);
  p.cov_px = Mat2::Identity() * 25.0;
  const int wide = windowHalfSize(p, o);
  p.blur_px = Vec2(20, 0);
  const int blurred = windowHalfSize(p, o);
  // ceil(3 * sd + 3 * 1.2 (default PSF sigma) + |blur| / 2)
  EXPECT_EQ(small, 4);     // 0.3 + 3.6
  EXPECT_EQ(wide, 19);     // 15 + 3.6
  EXPECT_EQ(blurred, 29);  // 15 + 3.6 + 10
  p.cov_px = Mat2::Identity() * 1e6;
  EXPECT_EQ(windowHalfSize(p, o), o.max_window_half_px);
}

TEST(Windows, StreakFoundAtItsMiddleAndFlagged) {
  // A star moving 12 px during the exposure: the sum of many positions along the streak.
  test::SimCamera cam;
  std::mt19937_64 rng(5);
  cv::Mat e = cv::Mat::zeros(100, 100, CV_64F);
  const Vec2 start(40.2, 50.4), blur(12.0, 3.0);
  for (int k = 0; k < 200; ++k) addGaussianStar(e, start + blur * (k + 0.5) / 200.0, 100.0, 1.0);
  const cv::Mat img = test::noisyFrame(e, cam, rng);
  PredictedStar p;
  p.px = start + 0.5 * blur + Vec2(1.0, -1.0);
  p.blur_px = blur;
  DetectorOptions o;
  o.gain_e_per_adu = cam.gain;
  const auto res = centroidWindows(img, {p}, o);
  ASSERT_TRUE(res[0].centroid.has_value()) << res[0].reason;
  EXPECT_LT((res[0].centroid->px - (start + 0.5 * blur)).norm(), 0.3);
  EXPECT_TRUE(res[0].centroid->flags & kElongated);
  // Full-frame detection keeps it (flagged) by default, rejects it when asked.
  const auto full = detectStars(img, o);
  ASSERT_EQ(full.stars.size(), 1u) << full.reason;
  EXPECT_TRUE(full.stars[0].flags & kElongated);
  o.reject_flags |= kElongated;
  EXPECT_TRUE(detectStars(img, o).stars.empty());
}

TEST(Prefilter, RemovesNoiseAtLowThresholdKeepsStars) {
  test::SimCamera cam;
  cam.psf_sigma = 2.0;  // defocused, as seed 004 recommends for WS centroiding
  std::mt19937_64 rng(9);
  const std::vector<test::SimStar> stars = {{Vec2(60.3, 60.6), 20000}, {Vec2(180.5, 140.2), 15000}};
  const cv::Mat img = test::renderFrame(256, 256, stars, cam, rng);
  DetectorOptions o;
  o.threshold_sigma = 1.5;
  o.max_stars = 1000;
  o.min_area = 1;
  const auto none = detectStars(img, o);
  for (const char* pf : {"neighbourhood", "grid"}) {
    o.prefilter = pf;
    const auto f = detectStars(img, o);
    EXPECT_LT(f.blobs_found * 10, none.blobs_found) << pf;
    int found = 0;
    for (const auto& s : stars)
      for (const auto& c : f.stars) found += (c.px - s.px).norm() < 0.5;
    EXPECT_EQ(found, 2) << pf;
  }
}

}  // namespace
}  // namespace st
