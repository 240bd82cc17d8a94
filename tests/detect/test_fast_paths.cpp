// The fast paths of detection against their slow references: the sparse run-based blob
// labelling against OpenCV's full-frame connected components, and the table-based pixel-
// integrated Gaussian against the libm erf/exp formula.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <tuple>

#include <opencv2/imgproc.hpp>

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
