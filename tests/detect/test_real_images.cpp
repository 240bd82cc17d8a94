// The eight real tetra3 frames (1024x768, 16-bit): enough stars, none counted twice.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include <opencv2/imgcodecs.hpp>

#include "sensors/detect/star_detector.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

double closestPair(const std::vector<Centroid>& s) {
  double best = 1e30;
  for (std::size_t i = 0; i < s.size(); ++i)
    for (std::size_t j = i + 1; j < s.size(); ++j) best = std::min(best, (s[i].px - s[j].px).norm());
  return best;
}

TEST(RealImages, EachTetra3FrameGivesTwentyDistinctStars) {
  const auto frames = test::tetra3Frames();
  ASSERT_EQ(frames.size(), 8u) << test::tetra3ImageDir();
  for (const std::string& path : frames) {
    const cv::Mat img = cv::imread(path, cv::IMREAD_UNCHANGED);
    ASSERT_EQ(img.type(), CV_16UC1) << path;
    const DetectionResult r = detectStars(img);
    std::printf("%s: %zu stars (blobs %d, rejected %d, duplicates %d) bg %.1f sigma %.2f ADU, "
                "closest pair %.1f px, brightest SNR %.0f\n",
                std::filesystem::path(path).filename().c_str(), r.stars.size(), r.blobs_found,
                r.rejected, r.duplicates, r.background, r.noise_sigma, closestPair(r.stars),
                r.stars.empty() ? 0.0 : r.stars.front().snr);
    EXPECT_TRUE(r.reason.empty()) << r.reason;
    EXPECT_GE(r.stars.size(), 20u) << path;
    EXPECT_GT(closestPair(r.stars), 2.0) << path;
    for (std::size_t i = 1; i < r.stars.size(); ++i)
      EXPECT_GE(r.stars[i - 1].flux, r.stars[i].flux) << "brightest first";
    for (const Centroid& c : r.stars) {
      EXPECT_GT(c.cov_px(0, 0), 0);
      EXPECT_GT(c.cov_px(1, 1), 0);
      EXPECT_GT(c.cov_px.determinant(), 0);
    }
  }
}

// The same frame as 8 bits (scaled) gives the bright stars at the same places.
TEST(RealImages, EightBitCopyAgrees) {
  const cv::Mat img16 = cv::imread(test::tetra3Frames().front(), cv::IMREAD_UNCHANGED);
  double lo, hi;
  cv::minMaxLoc(img16, &lo, &hi);
  cv::Mat img8;
  img16.convertTo(img8, CV_8U, 255.0 / hi);
  DetectorOptions o;
  o.max_stars = 10;
  const auto a = detectStars(img16, o), b = detectStars(img8, o);
  ASSERT_GE(b.stars.size(), 5u) << b.reason;
  int matched = 0;
  for (const auto& s : b.stars)
    for (const auto& t : a.stars) matched += (s.px - t.px).norm() < 0.5;
  EXPECT_GE(matched, 5);
}

}  // namespace
}  // namespace st
