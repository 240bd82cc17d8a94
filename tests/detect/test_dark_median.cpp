// The master dark of seed 004 sec. 4.1 is a per-pixel median: a cosmic ray (or a satellite)
// present in one of five dark exposures must not end up in it, where a mean would keep a
// fifth of it.
#include <gtest/gtest.h>

#include <random>

#include <opencv2/imgproc.hpp>

#include "sensors/detect/dark_frame.hpp"

namespace st {
namespace {

std::vector<cv::Mat> darkExposures(int n, int type, double level, double sigma, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(level, sigma);
  std::vector<cv::Mat> frames;
  for (int k = 0; k < n; ++k) {
    cv::Mat f(48, 64, type);
    for (int y = 0; y < f.rows; ++y)
      for (int x = 0; x < f.cols; ++x) {
        const double v = noise(rng) + (x == 5 && y == 9 ? 120 : 0);  // one hot pixel, fixed
        if (type == CV_8UC1)
          f.at<uint8_t>(y, x) = cv::saturate_cast<uint8_t>(v);
        else
          f.at<uint16_t>(y, x) = cv::saturate_cast<uint16_t>(v);
      }
    frames.push_back(f);
  }
  return frames;
}

TEST(DarkMedian, RejectsACosmicRayInOneOfFiveFrames) {
  for (const int type : {CV_16UC1, CV_8UC1}) {
    std::vector<cv::Mat> frames = darkExposures(5, type, 40, 2, 11);
    const int peak = type == CV_8UC1 ? 255 : 30000;
    cv::line(frames[3], {30, 20}, {32, 20}, cv::Scalar(peak));  // a cosmic-ray track
    const cv::Mat dark = medianDark(frames);
    ASSERT_EQ(dark.type(), type);
    cv::Mat mean_stack = cv::Mat::zeros(dark.size(), CV_64F);
    for (const auto& f : frames) cv::accumulate(f, mean_stack);
    mean_stack /= 5.0;
    cv::Mat d;
    dark.convertTo(d, CV_64F);
    for (int t = 0; t < 3; ++t) {
      // Within 5 sigma of the level: the median of four noisy values and the outlier.
      EXPECT_NEAR(d.at<double>(20, 30 + t), 40, 10) << "cosmic ray kept, type " << type;
      EXPECT_GT(mean_stack.at<double>(20, 30 + t), 40 + 0.15 * peak);  // what a mean keeps
    }
    EXPECT_NEAR(d.at<double>(9, 5), 160, 10) << "the fixed hot pixel must stay";
    const DarkStats st = darkStats(dark, 5.0);
    EXPECT_NEAR(st.sigma, 2.0 * 0.6, 1.0);  // the median of 5 has ~0.54 of one frame's sigma
    EXPECT_EQ(st.hot_pixels, 1);
  }
}

TEST(DarkMedian, EvenCountTakesTheLowerMiddle) {
  std::vector<cv::Mat> frames;
  for (int v : {10, 40, 20, 30}) frames.emplace_back(16, 16, CV_16UC1, cv::Scalar(v));
  EXPECT_EQ(medianDark(frames).at<uint16_t>(3, 3), 20);
}

}  // namespace
}  // namespace st
