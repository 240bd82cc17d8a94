// The fast paths of detection against their slow references: the sparse run-based blob
// labelling against OpenCV's full-frame connected components, the table-based pixel-
// integrated Gaussian against the libm erf/exp formula, and the histogram quantiles of a
// window's border ring against a sort.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <tuple>

#include <opencv2/imgproc.hpp>

#include "sensors/detect/background.hpp"
#include "sensors/detect/blob_labeller.hpp"
#include "sensors/detect/pixel_gaussian.hpp"

namespace st {
namespace {

using BlobKey = std::tuple<int, int, int, int, int, double>;  // area, box, raw sum

std::vector<BlobKey> referenceBlobs(const cv::Mat& mask, const cv::Mat& grey, int connectivity) {
  cv::Mat labels, stats, cents;
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, cents, connectivity, CV_32S);
  std::vector<double> sums(static_cast<std::size_t>(n), 0.0);
  for (int y = 0; y < mask.rows; ++y)
    for (int x = 0; x < mask.cols; ++x)
      sums[static_cast<std::size_t>(labels.at<int>(y, x))] += grey.at<uint16_t>(y, x);
  std::vector<BlobKey> out;
  for (int l = 1; l < n; ++l) {
    const int* s = stats.ptr<int>(l);
    out.emplace_back(s[cv::CC_STAT_AREA], s[0], s[1], s[2], s[3], sums[static_cast<std::size_t>(l)]);
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<BlobKey> labellerBlobs(const BlobLabeller& lab) {
  std::vector<BlobKey> out;
  for (const Blob& b : lab.blobs()) {
    const cv::Rect r = b.box();
    out.emplace_back(b.area, r.x, r.y, r.width, r.height, b.sum_raw);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Random 16-bit frames whose above-threshold pixels form blobs of every shape: sparse
// speckle, dense clusters, U-shapes that only join rows later, blobs on the borders.
TEST(BlobLabeller, SameBlobsAsOpenCvConnectedComponents) {
  std::mt19937_64 rng(21);
  for (int trial = 0; trial < 24; ++trial) {
    const int w = 37 + trial * 11, h = 23 + trial * 7;
    cv::Mat grey(h, w, CV_16U);
    cv::randu(grey, 0, 1000);
    const double fill = 0.02 + 0.03 * (trial % 10);  // up to 29% above the threshold
    const double thr = 1000.0 * (1.0 - fill);
    // Tiled thresholds (tile 16), varied per tile, as the detector builds them.
    const int tile = trial % 2 ? 16 : 0;
    const int tx = tile ? (w + tile - 1) / tile : 1, ty = tile ? (h + tile - 1) / tile : 1;
    std::vector<double> thresholds(static_cast<std::size_t>(tx * ty));
    std::uniform_real_distribution<double> jitter(-30, 30);
    for (double& t : thresholds) t = thr + jitter(rng) + 0.5;
    cv::Mat mask(h, w, CV_8U);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const double t = thresholds[static_cast<std::size_t>(tile ? (y / tile) * tx + x / tile : 0)];
        mask.at<uint8_t>(y, x) = grey.at<uint16_t>(y, x) > t ? 255 : 0;
      }
    BlobLabeller lab;
    lab.labelThreshold(grey, tile, tx, thresholds);
    const auto ref = referenceBlobs(mask, grey, 8);
    EXPECT_EQ(labellerBlobs(lab), ref) << "trial " << trial;
    // The same through the mask entry point (used with the pre-filters).
    BlobLabeller lab2;
    lab2.labelMask(mask, grey);
    EXPECT_EQ(labellerBlobs(lab2), ref) << "trial " << trial;
    // Every pixel of every blob exactly once, and each blob's peak is its first maximum.
    int pixels = 0;
    for (const Blob& b : lab.blobs()) {
      double best = -1;
      cv::Point first;
      lab.forEachPixel(grey, b, [&](int x, int y, double v) {
        ++pixels;
        EXPECT_TRUE(mask.at<uint8_t>(y, x));
        if (v > best) {
          best = v;
          first = {x, y};
        }
      });
      EXPECT_EQ(first, b.peak);
      EXPECT_EQ(best, b.peak_raw);
    }
    EXPECT_EQ(pixels, cv::countNonZero(mask));
    // Teeth: 4-connected components differ on these random masks.
    if (fill > 0.1) {
      EXPECT_NE(referenceBlobs(mask, grey, 4), ref) << "trial " << trial;
    }
  }
}

TEST(BlobLabeller, EightBitAndEdgeCases) {
  cv::Mat grey = cv::Mat::zeros(5, 40, CV_8U);
  BlobLabeller lab;
  lab.labelThreshold(grey, 0, 1, {0.0});
  EXPECT_TRUE(lab.blobs().empty());
  lab.labelThreshold(grey, 0, 1, {-1.0});  // below every value: the whole frame is one blob
  ASSERT_EQ(lab.blobs().size(), 1u);
  EXPECT_EQ(lab.blobs()[0].area, 200);
  // Two diagonal pixels are one 8-connected blob; a run crossing the SIMD block boundary.
  grey.at<uint8_t>(1, 1) = 9;
  grey.at<uint8_t>(2, 2) = 9;
  for (int x = 10; x < 40; ++x) grey.at<uint8_t>(4, x) = 200;
  lab.labelThreshold(grey, 0, 1, {5.0});
  ASSERT_EQ(lab.blobs().size(), 2u);
  EXPECT_EQ(lab.blobs()[0].area, 2);
  EXPECT_EQ(lab.blobs()[1].area, 30);
  EXPECT_EQ(lab.blobs()[1].box(), cv::Rect(10, 4, 30, 1));
  lab.labelThreshold(grey, 0, 1, {255.0});  // nothing is above the type's maximum
  EXPECT_TRUE(lab.blobs().empty());
}

// The Hermite-table pixel integrals agree with erf/exp to 1e-8 everywhere, centre and tails,
// narrow and wide PSFs.
TEST(PixelGaussian, RowMatchesReference) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  double worst = 0, worst_shifted = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int n = 1 + static_cast<int>(u(rng) * 40);
    const double a0 = std::floor(-20 + 40 * u(rng));
    const double s = 0.3 + 9.7 * u(rng) * u(rng);
    const double x = a0 - 3 + (n + 6) * u(rng);
    std::vector<double> f(static_cast<std::size_t>(n)), dx(f.size()), ds(f.size());
    pixelGaussianRow(n, a0, x, s, f.data(), dx.data(), ds.data());
    for (int k = 0; k < n; ++k) {
      const std::size_t i = static_cast<std::size_t>(k);
      const PixelGaussian1d r = pixelGaussian1d(a0 + k, x, s);
      worst = std::max({worst, std::abs(f[i] - r.f), std::abs(dx[i] - r.df_dx) * s,
                        std::abs(ds[i] - r.df_ds) * s});
      // Teeth: a 1e-4 px shift of the centre is visible at this tolerance.
      const PixelGaussian1d q = pixelGaussian1d(a0 + k, x + 1e-4, s);
      worst_shifted = std::max(worst_shifted, std::abs(f[i] - q.f));
    }
  }
  EXPECT_LT(worst, 1e-8);
  EXPECT_GT(worst_shifted, 1e-6);
}

}  // namespace
}  // namespace st

namespace st {
namespace {

// The definition: grouped quantile of sorted samples quantised with `step` (0: not quantised).
double referenceQuantile(std::vector<float> v, double p, double step) {
  std::sort(v.begin(), v.end());
  const double target = p * static_cast<double>(v.size());
  const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(target));
  const float m = v[k];
  if (step == 0) return m;
  const auto [lo, hi] = std::equal_range(v.begin(), v.end(), m);
  const double below = static_cast<double>(lo - v.begin());
  return m + step * (-0.5 + (target - below) / static_cast<double>(hi - lo));
}

void expectReference(std::vector<float> v, double step, const char* what) {
  const double level = referenceQuantile(v, 0.5, step);
  const double sigma = (referenceQuantile(v, 0.75, step) - referenceQuantile(v, 0.25, step)) / 1.349;
  double l = 0, s = 0;
  robustLevelSigma(v, l, s);
  EXPECT_NEAR(l, level, 1e-9) << what;
  EXPECT_NEAR(s, sigma, 1e-9) << what;
}

TEST(RobustLevelSigma, HistogramAndSelectionAgreeWithTheSortedDefinition) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 8 + trial % 150;  // window rings from 3x3 to ~40x40
    std::normal_distribution<double> noise(1000.0, trial % 2 ? 1.3 : 25.0);
    std::vector<float> adu(static_cast<std::size_t>(n));
    for (auto& x : adu) x = static_cast<float>(std::lround(noise(rng)));
    // 8/16-bit pixels (step 1; a short list is not trusted to tell a step).
    expectReference(adu, 1.0, "step 1");
    if (n < 24) continue;
    // 12-bit pixels shifted into 16 bits: steps of 16.
    std::vector<float> shifted = adu;
    for (auto& x : shifted) x *= 16;
    expectReference(shifted, 16.0, "step 16");
    // A star on the ring: a few values far above the histogram (overflow), same quantiles.
    std::vector<float> star = shifted;
    for (int i = 0; i < n / 10; ++i) star[static_cast<std::size_t>(3 * i)] = 65520;
    expectReference(star, 16.0, "star on the ring");
    // Not whole numbers (a dark-subtracted float frame): plain order statistics.
    std::vector<float> real = adu;
    for (auto& x : real) x += 0.25f;
    expectReference(real, 0.0, "not quantised");
  }
}

TEST(RobustLevelSigma, ScalesWithTheQuantisationStep) {
  // Grouped data with the step taken from the data: the same pixels read by a 12-bit camera
  // (step 1) and shifted into a 16-bit word (step 16) give 16x the level and sigma. Treating
  // the 16-bit values as step-1 data (the width of the rounding interval wrong by 16x) would
  // not.
  std::mt19937 rng(9);
  std::normal_distribution<double> noise(200.0, 1.1);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<float> v(56), w;
    for (auto& x : v) x = static_cast<float>(std::lround(noise(rng)));
    for (float x : v) w.push_back(16 * x);
    double l1, s1, l16, s16;
    robustLevelSigma(v, l1, s1);
    robustLevelSigma(w, l16, s16);
    EXPECT_NEAR(l16, 16 * l1, 1e-9);
    EXPECT_NEAR(s16, 16 * s1, 1e-9);
    // An 8-bit frame written as 16 bits by a converter: x256, or x257 (255 -> 65535), with
    // an offset. The step is the common divisor of the differences, not only a power of two.
    for (const double k : {256.0, 257.0, 3.0}) {
      std::vector<float> u;
      for (float x : v) u.push_back(static_cast<float>(k * x + 5 * k));
      double lk, sk;
      robustLevelSigma(u, lk, sk);
      EXPECT_NEAR(lk, k * (l1 + 5), 1e-6 * k) << k;
      EXPECT_NEAR(sk, k * s1, 1e-6 * k) << k;
    }
  }
}

}  // namespace
}  // namespace st
