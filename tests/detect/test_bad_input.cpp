// Bad images give an empty result with a reason, never a crash; bad options throw.
#include <gtest/gtest.h>

#include <mrpt/img/CImage.h>

#include "common/errors.hpp"
#include <opencv2/imgproc.hpp>

#include "sensors/detect/centroider.hpp"
#include "sensors/detect/star_detector.hpp"
#include "sensors/mrpt/image_detect.hpp"
#include "tests/detect/sim_frame.hpp"

namespace st {
namespace {

void expectEmptyWithReason(const cv::Mat& img, const std::string& what) {
  const DetectionResult r = detectStars(img);
  EXPECT_TRUE(r.stars.empty()) << what;
  EXPECT_FALSE(r.reason.empty()) << what;
  const auto w = centroidWindows(img, {PredictedStar{Vec2(5, 5), Mat2::Identity(), Vec2::Zero()}});
  ASSERT_EQ(w.size(), 1u);
  EXPECT_FALSE(w[0].centroid.has_value()) << what;
  EXPECT_FALSE(w[0].reason.empty()) << what;
}

TEST(BadInput, EmptyResultWithReason) {
  expectEmptyWithReason(cv::Mat(), "empty");
  expectEmptyWithReason(cv::Mat(64, 64, CV_32F, cv::Scalar(10)), "float");
  expectEmptyWithReason(cv::Mat(64, 64, CV_8S, cv::Scalar(10)), "signed");
  expectEmptyWithReason(cv::Mat(64, 64, CV_8UC2, cv::Scalar(10, 10)), "two channels");
  expectEmptyWithReason(cv::Mat(64, 64, CV_16U, cv::Scalar(65535)), "all saturated 16-bit");
  expectEmptyWithReason(cv::Mat(64, 64, CV_8U, cv::Scalar(255)), "all saturated 8-bit");
  expectEmptyWithReason(cv::Mat(64, 64, CV_16U, cv::Scalar(0)), "all black");
  expectEmptyWithReason(cv::Mat(1, 1, CV_8U, cv::Scalar(0)), "one pixel");
  expectEmptyWithReason(cv::Mat(3, 2000, CV_16U, cv::Scalar(7)), "thin constant");
  EXPECT_NE(detectStars(cv::Mat()).reason.find("empty"), std::string::npos);
  EXPECT_NE(detectStars(cv::Mat(64, 64, CV_16U, cv::Scalar(65535))).reason.find("saturated"),
            std::string::npos);
  EXPECT_NE(detectStars(cv::Mat(64, 64, CV_16U, cv::Scalar(0))).reason.find("blank"),
            std::string::npos);
  // A dark frame of the wrong size is bad input of the image kind: a reason, no throw.
  DetectorOptions o;
  o.dark_frame = cv::Mat(10, 10, CV_16U, cv::Scalar(0));
  EXPECT_FALSE(detectStars(cv::Mat(64, 64, CV_16U, cv::Scalar(5)), o).reason.empty());
}

TEST(BadInput, PureNoiseGivesNoStars) {
  std::mt19937_64 rng(7);
  const cv::Mat img = test::renderFrame(256, 256, {}, test::SimCamera{}, rng);
  const DetectionResult r = detectStars(img);
  EXPECT_LE(r.stars.size(), 1u) << "5 sigma on 65k Gaussian pixels: ~0.02 false pixels";
}

TEST(BadInput, InvalidOptionsThrowNamingTheField) {
  const cv::Mat img(32, 32, CV_16U, cv::Scalar(100));
  auto expectThrow = [&](DetectorOptions o, const std::string& field) {
    std::string err;
    EXPECT_FALSE(o.isValid(&err));
    EXPECT_NE(err.find(field), std::string::npos) << err;
    EXPECT_THROW(detectStars(img, o), InputError);
  };
  DetectorOptions o;
  EXPECT_TRUE(o.isValid());
  o.gain_e_per_adu = 0;
  expectThrow(o, "gain_e_per_adu");
  o = {};
  o.centroider = "magic";
  expectThrow(o, "magic");
  o = {};
  o.prefilter = "median";
  expectThrow(o, "prefilter");
  o = {};
  o.max_area = 1;
  o.min_area = 5;
  expectThrow(o, "max_area");
  o = {};
  o.threshold_sigma = -1;
  expectThrow(o, "threshold_sigma");
}

TEST(Inputs, EightBitColourAndCImageAgree) {
  std::mt19937_64 rng(3);
  test::SimCamera cam;
  const std::vector<test::SimStar> stars = {{Vec2(40.3, 50.7), 20000}, {Vec2(90.6, 20.2), 8000}};
  const cv::Mat img16 = test::renderFrame(128, 96, stars, cam, rng);
  const DetectionResult a = detectStars(img16);
  ASSERT_EQ(a.stars.size(), 2u) << a.reason;
  cv::Mat img8, colour;
  img16.convertTo(img8, CV_8U, 0.5, -20);
  cv::cvtColor(img8, colour, cv::COLOR_GRAY2BGR);
  const mrpt::img::CImage cimg(img16, mrpt::img::SHALLOW_COPY);
  for (const DetectionResult& r : {detectStars(img8), detectStars(colour), detectStars(cimg)}) {
    ASSERT_EQ(r.stars.size(), 2u) << r.reason;
    for (int k = 0; k < 2; ++k) EXPECT_LT((r.stars[k].px - stars[k].px).norm(), 0.3);
  }
  EXPECT_TRUE(detectStars(mrpt::img::CImage()).stars.empty());
}

TEST(Inputs, RegistryListsAllCentroiders) {
  // The library's table first, in order; members registered by this test executable follow.
  const auto names = Centroider::names();
  ASSERT_GE(names.size(), 3u);
  EXPECT_EQ(std::vector<std::string>(names.begin(), names.begin() + 3),
            (std::vector<std::string>{"cog", "iwc", "gauss"}));
  for (const auto& n : names) EXPECT_NE(Centroider::help().find(n), std::string::npos);
  std::string err;
  EXPECT_EQ(Centroider::create("nope", &err), nullptr);
  EXPECT_NE(err.find("gauss"), std::string::npos);
}

}  // namespace
}  // namespace st
