// StarDetector: options validated once (at construction), then frame after frame with the
// same results as the one-shot free functions, whatever came before (grey or colour input,
// other sizes, other windows): the reused scratch buffers must not leak between frames.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "common/errors.hpp"
#include "sensors/detect/star_detector.hpp"
#include "tests/detect/sim_frame.hpp"

namespace st {
namespace {

void expectSameStars(const DetectionResult& a, const DetectionResult& b) {
  EXPECT_EQ(a.reason, b.reason);
  ASSERT_EQ(a.stars.size(), b.stars.size());
  for (std::size_t k = 0; k < a.stars.size(); ++k) {
    EXPECT_EQ(a.stars[k].px, b.stars[k].px) << k;
    EXPECT_EQ(a.stars[k].cov_px, b.stars[k].cov_px) << k;
  }
}

std::vector<cv::Mat> frames(const test::SimCamera& cam) {
  std::mt19937_64 rng(3);
  std::vector<cv::Mat> out;
  out.push_back(test::renderFrame(160, 120, {{Vec2(40.3, 50.6), 8000}, {Vec2(100.2, 30.9), 5000}},
                                  cam, rng));
  out.push_back(test::renderFrame(96, 80, {{Vec2(20.5, 60.1), 6000}}, cam, rng));
  cv::Mat colour;
  cv::Mat eight;
  out[0].convertTo(eight, CV_8U, 0.25);  // peaks ~200 ADU: unsaturated
  cv::cvtColor(eight, colour, cv::COLOR_GRAY2BGR);
  out.push_back(colour);
  out.push_back(eight);  // same size and depth as the colour frame's conversion
  return out;
}

TEST(StarDetectorObject, ReusedDetectorMatchesOneShotCalls) {
  const test::SimCamera cam;
  const DetectorOptions opts = test::detectorOptionsFor(cam);
  StarDetector det(opts);
  const std::vector<cv::Mat> fs = frames(cam);
  DetectionResult reused;
  for (int pass = 0; pass < 2; ++pass)
    for (std::size_t f = 0; f < fs.size(); ++f) {
      SCOPED_TRACE("frame " + std::to_string(f));
      const DetectionResult once = detectStars(fs[f], opts);
      EXPECT_FALSE(once.stars.empty()) << once.reason;
      expectSameStars(det.detect(fs[f]), once);
      det.detect(fs[f], reused);
      expectSameStars(reused, once);
      EXPECT_EQ(reused.blobs_found, once.blobs_found);
      // A frame without stars empties a reused result (nothing stale survives).
      det.detect(cv::Mat(40, 40, CV_16U, cv::Scalar(7)), reused);
      EXPECT_TRUE(reused.stars.empty());
      EXPECT_NE(reused.reason.find("blank"), std::string::npos) << reused.reason;
    }
  // The caller's pixels are never written (the colour frame's conversion is scratch).
  cv::Mat eight = fs[3].clone();
  det.detect(fs[3]);
  det.detect(fs[2]);
  EXPECT_EQ(cv::norm(eight, fs[3], cv::NORM_INF), 0.0);
}

TEST(StarDetectorObject, WindowsReuseTheOutputVector) {
  const test::SimCamera cam;
  const DetectorOptions opts = test::detectorOptionsFor(cam);
  StarDetector det(opts);
  const std::vector<cv::Mat> fs = frames(cam);
  const std::vector<PredictedStar> two = {{Vec2(40.6, 50.2), Mat2::Identity(), Vec2::Zero()},
                                          {Vec2(100, 31), Mat2::Identity(), Vec2::Zero()}};
  const std::vector<PredictedStar> one_off = {{Vec2(-50, 5), Mat2::Identity(), Vec2::Zero()}};
  std::vector<WindowResult> out;
  for (int pass = 0; pass < 2; ++pass) {
    det.centroidWindows(fs[0], two, out);
    const auto once = centroidWindows(fs[0], two, opts);
    ASSERT_EQ(out.size(), 2u);
    for (std::size_t k = 0; k < 2; ++k) {
      ASSERT_TRUE(out[k].centroid.has_value()) << out[k].reason;
      EXPECT_TRUE(out[k].reason.empty());
      EXPECT_EQ(out[k].centroid->px, once[k].centroid->px);
    }
    det.centroidWindows(fs[0], one_off, out);  // a stale centroid must not survive
    ASSERT_EQ(out.size(), 1u);
    EXPECT_FALSE(out[0].centroid.has_value());
    EXPECT_EQ(out[0].reason, "outside image");
  }
}

TEST(StarDetectorObject, InvalidOptionsRefusedAtConstruction) {
  DetectorOptions o;
  o.centroider = "nope";
  std::string why;
  EXPECT_EQ(StarDetector::create(o, &why), nullptr);
  EXPECT_NE(why.find("DetectorOptions.centroider"), std::string::npos) << why;
  EXPECT_THROW(StarDetector{o}, InputError);
  o = {};
  o.threshold_sigma = 0;
  EXPECT_EQ(StarDetector::create(o, &why), nullptr);
  EXPECT_NE(why.find("threshold_sigma"), std::string::npos) << why;
  EXPECT_NE(StarDetector::create(DetectorOptions{}, &why), nullptr);
}

}  // namespace
}  // namespace st
