// Teeth for dark-frame subtraction (issue 17 item 1): warm pixel clusters of the sensor's
// dark signal look like stars (same PSF-sized blob, same brightness); the dark frame is what
// tells them apart. A frame holds 10 stars and 6 warm clusters; the master dark holds the
// clusters (and the bias) without noise.
#include <gtest/gtest.h>

#include <cstdio>

#include "sensors/detect/star_detector.hpp"
#include "tests/detect/sim_frame.hpp"

namespace st {
namespace {

struct DarkScene {
  cv::Mat frame, dark;
  std::vector<Vec2> stars, warm;
  test::SimCamera cam;
};

DarkScene darkScene(uint64_t seed) {
  DarkScene s;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int w = 320, h = 240;
  // A 4 x 4 grid of sites 60 px apart, each a star or a warm cluster (never close together).
  std::vector<Vec2> sites;
  for (int gy = 0; gy < 4; ++gy)
    for (int gx = 0; gx < 4; ++gx)
      sites.push_back(Vec2(40 + 75 * gx + 10 * u(rng), 30 + 55 * gy + 10 * u(rng)));
  std::shuffle(sites.begin(), sites.end(), rng);
  s.stars.assign(sites.begin(), sites.begin() + 10);
  s.warm.assign(sites.begin() + 10, sites.end());
  cv::Mat stars_e = cv::Mat::zeros(h, w, CV_64F), dark_e = cv::Mat::zeros(h, w, CV_64F);
  for (const Vec2& p : s.stars) addGaussianStar(stars_e, p, 20000.0, s.cam.psf_sigma);
  for (const Vec2& p : s.warm) addGaussianStar(dark_e, p, 20000.0, s.cam.psf_sigma);
  s.frame = test::noisyFrame(stars_e + dark_e, s.cam, rng);
  // The master dark: the mean of many dark exposures (the dark signal and the bias, in ADU).
  dark_e.convertTo(s.dark, CV_16U, 1.0 / s.cam.gain, s.cam.bias_adu);
  return s;
}

int foundNear(const DetectionResult& r, const std::vector<Vec2>& where, double radius_px) {
  int n = 0;
  for (const Vec2& p : where)
    for (const Centroid& c : r.stars)
      if ((c.px - p).norm() < radius_px) {
        ++n;
        break;
      }
  return n;
}

TEST(DetectRules, DarkFrameSubtractionRemovesWarmClusters) {
  const DarkScene s = darkScene(3);
  DetectorOptions o = test::detectorOptionsFor(s.cam);
  // Teeth: without the dark frame the warm clusters are detected as stars.
  const DetectionResult raw = StarDetector(o).detect(s.frame);
  const int warm_raw = foundNear(raw, s.warm, 3.0);
  std::printf("without the dark frame: %zu detections, %d of %zu warm clusters\n",
              raw.stars.size(), warm_raw, s.warm.size());
  EXPECT_GE(warm_raw, 5);

  o.dark_frame = s.dark;
  const DetectionResult r = StarDetector(o).detect(s.frame);
  std::printf("with the dark frame: %zu detections, %d of %zu warm clusters, %d of %zu stars\n",
              r.stars.size(), foundNear(r, s.warm, 3.0), s.warm.size(),
              foundNear(r, s.stars, 0.5), s.stars.size());
  EXPECT_EQ(foundNear(r, s.warm, 3.0), 0);
  EXPECT_EQ(foundNear(r, s.stars, 0.5), static_cast<int>(s.stars.size()));
}

// The windows of tracking subtract the dark frame as full-frame detection does (found by this
// audit: they read the raw image, and a window on a warm cluster found a "star" in 6 of 6).
TEST(DetectRules, WindowsSubtractTheDarkFrameToo) {
  const DarkScene s = darkScene(3);
  DetectorOptions o = test::detectorOptionsFor(s.cam);
  o.dark_frame = s.dark;
  std::vector<PredictedStar> pred;
  for (const Vec2& p : s.warm) pred.push_back({p, Mat2::Identity() * 0.25, Vec2::Zero()});
  std::vector<WindowResult> out;
  StarDetector(o).centroidWindows(s.frame, pred, out);
  int found = 0;
  for (const WindowResult& w : out) found += w.centroid.has_value();
  // Without the subtraction 6 of 6 windows find a "star" on their warm cluster. With it, what
  // is left is the warm pixels' own shot noise (not in the window's noise model, which knows
  // sky and read noise): measured 1 of 6 windows on such a noise peak, which tracking's gate
  // then judges against the predicted position.
  EXPECT_LE(found, 1) << "windows on warm clusters found centroids: the dark frame was ignored";
}

}  // namespace
}  // namespace st
