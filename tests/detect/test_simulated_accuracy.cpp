// The shared suite of the centroider family: every centroider in the registry (TEST_P over
// Centroider::names(), including those a test file of this executable registers) on simulated
// stars: consistency of the reported covariance (normalised error squared ~ chi2(2)), no bias
// across sub-pixel phases; and the Gaussian fit against the Cramer-Rao bound.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "sensors/detect/centroider.hpp"
#include "sensors/detect/star_detector.hpp"
#include "tests/detect/sim_frame.hpp"

namespace st {
namespace {

struct Trial {
  std::vector<Vec2> err;     // estimate - truth [px]
  std::vector<Vec2> truth;
  std::vector<Mat2> cov;     // reported
  std::vector<Mat2> crb;     // Cramer-Rao (x, y only: F, B, s known — the tighter bound)
  std::vector<Mat2> crb_full;  // F, B, s also unknown
  std::vector<double> snr;
  int missed = 0;
};

// 25 frames x 40 stars = 1,000 stars at random sub-pixel positions, one flux.
Trial runTrial(const std::string& centroider, double flux_e, uint64_t seed) {
  test::SimCamera cam;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  DetectorOptions opts = test::detectorOptionsFor(cam);
  opts.centroider = centroider;
  Trial t;
  for (int frame = 0; frame < 25; ++frame) {
    std::vector<test::SimStar> stars;
    for (int gy = 0; gy < 5; ++gy)
      for (int gx = 0; gx < 8; ++gx)  // a 24 px grid, random phase: stars never blend
        stars.push_back({Vec2(14 + 24 * gx + 6 * u(rng), 14 + 24 * gy + 6 * u(rng)), flux_e});
    const cv::Mat img = test::renderFrame(214, 142, stars, cam, rng);
    const DetectionResult res = detectStars(img, opts);
    for (const auto& s : stars) {
      const Centroid* best = nullptr;
      for (const auto& c : res.stars)
        if ((c.px - s.px).norm() < 1.5 && (!best || (c.px - s.px).norm() < (best->px - s.px).norm()))
          best = &c;
      if (!best) {
        ++t.missed;
        continue;
      }
      t.err.push_back(best->px - s.px);
      t.truth.push_back(s.px);
      t.cov.push_back(best->cov_px);
      t.crb.push_back(test::cramerRaoXY(s.px, flux_e, cam, false));
      t.crb_full.push_back(test::cramerRaoXY(s.px, flux_e, cam, true));
      t.snr.push_back(best->snr);
    }
  }
  return t;
}

double meanNees(const Trial& t, double cov_scale) {
  double s = 0;
  for (std::size_t i = 0; i < t.err.size(); ++i)
    s += t.err[i].dot((cov_scale * t.cov[i]).inverse() * t.err[i]);
  return s / static_cast<double>(t.err.size());
}

// Mean of chi2(2) over n samples: 2 +- 2/sqrt(n); the band is 2 +- 0.3.
bool neesConsistent(double m) { return m > 1.7 && m < 2.3; }

// Every phase bin's mean error within 4 standard errors of 0 (8 bins, both axes).
bool unbiasedAcrossPhases(const Trial& t, const std::vector<Vec2>& err) {
  for (int axis = 0; axis < 2; ++axis)
    for (int b = 0; b < 4; ++b) {
      double s = 0, s2 = 0;
      int n = 0;
      for (std::size_t i = 0; i < err.size(); ++i) {
        const double ph = t.truth[i][axis] - std::floor(t.truth[i][axis]);
        if (static_cast<int>(ph * 4) != b) continue;
        s += err[i][axis];
        s2 += err[i][axis] * err[i][axis];
        ++n;
      }
      if (n < 30) return false;
      const double m = s / n, sd = std::sqrt(s2 / n - m * m);
      if (std::abs(m) > 4 * sd / std::sqrt(n)) return false;
    }
  return true;
}

struct Summary {
  double rms, crb_rms, crb_full_rms, nees, median_snr;
};
Summary summarise(const Trial& t) {
  double e2 = 0, c = 0, cf = 0;
  for (std::size_t i = 0; i < t.err.size(); ++i) {
    e2 += t.err[i].squaredNorm();
    c += t.crb[i].trace();
    cf += t.crb_full[i].trace();
  }
  const double n = static_cast<double>(t.err.size());
  std::vector<double> snr = t.snr;
  std::nth_element(snr.begin(), snr.begin() + static_cast<long>(snr.size() / 2), snr.end());
  return {std::sqrt(e2 / n), std::sqrt(c / n), std::sqrt(cf / n), meanNees(t, 1.0),
          snr[snr.size() / 2]};
}

class CentroidAccuracy : public ::testing::TestWithParam<std::string> {};

TEST_P(CentroidAccuracy, CovarianceConsistentAndUnbiased) {
  for (double flux : {3000.0, 12000.0}) {
    const Trial t = runTrial(GetParam(), flux, 42);
    const Summary s = summarise(t);
    std::printf("[%s flux %.0f e-] n=%zu missed=%d rms=%.4f px CRB(xy)=%.4f CRB(all)=%.4f "
                "ratio=%.3f NEES=%.3f median SNR=%.1f\n",
                GetParam().c_str(), flux, t.err.size(), t.missed, s.rms, s.crb_rms,
                s.crb_full_rms, s.rms / s.crb_rms, s.nees, s.median_snr);
    ASSERT_GE(t.err.size(), 990u);
    EXPECT_GE(s.median_snr, 20.0);
    EXPECT_TRUE(neesConsistent(s.nees)) << s.nees;
    EXPECT_FALSE(neesConsistent(meanNees(t, 2.0))) << "teeth: a 2x covariance must fail";
    EXPECT_FALSE(neesConsistent(meanNees(t, 0.5))) << "teeth: a 0.5x covariance must fail";
    EXPECT_TRUE(unbiasedAcrossPhases(t, t.err));
    // Teeth: an estimator snapped to the pixel grid has a phase-dependent bias.
    std::vector<Vec2> snapped;
    for (std::size_t i = 0; i < t.err.size(); ++i) {
      const Vec2 est = t.truth[i] + t.err[i];
      snapped.push_back(Vec2(std::round(est.x()), std::round(est.y())) - t.truth[i]);
    }
    EXPECT_FALSE(unbiasedAcrossPhases(t, snapped));
    if (GetParam() == "gauss") {
      // The acceptance: within 1.3x of the Cramer-Rao bound (the tighter, x-y only).
      EXPECT_LE(s.rms, 1.3 * s.crb_rms);
      EXPECT_GE(s.rms, 0.9 * s.crb_rms) << "better than the bound: the test is broken";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllCentroiders, CentroidAccuracy,
                         ::testing::ValuesIn(Centroider::names()),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace st
