#include "sensors/detect/star_detector.hpp"

#include <algorithm>
#include <cmath>
#include <exception>

#include <opencv2/imgproc.hpp>

#include "common/check.hpp"
#include "common/cpu_clones.hpp"
#include "common/errors.hpp"
#include "sensors/detect/detect_internal.hpp"

namespace st {
namespace detect_detail {

bool greyView(const cv::Mat& in, cv::Mat& converted, cv::Mat& grey, std::string& reason) {
  if (in.empty()) {
    reason = "empty image";
    return false;
  }
  if (in.depth() != CV_8U && in.depth() != CV_16U) {
    reason = "unsupported image type " + cv::typeToString(in.type()) + " (want 8- or 16-bit)";
    return false;
  }
  if (in.channels() == 1) {
    grey = in;
    return true;
  }
  if (in.channels() == 3) {
    cv::cvtColor(in, converted, cv::COLOR_BGR2GRAY);
  } else if (in.channels() == 4) {
    cv::cvtColor(in, converted, cv::COLOR_BGRA2GRAY);
  } else {
    reason = "unsupported image type " + cv::typeToString(in.type()) + " (channels)";
    return false;
  }
  grey = converted;
  return true;
}

Mat2 Moments::central() const {
  Mat2 m = Mat2::Zero();
  if (sw <= 0) return m;
  const double mx = sx / sw, my = sy / sw;
  m(0, 0) = sxx / sw - mx * mx;
  m(1, 1) = syy / sw - my * my;
  m(0, 1) = m(1, 0) = sxy / sw - mx * my;
  return m;
}

void Moments::shape(double& elongation, double& sigma, double y_scale) const {
  elongation = 1;
  sigma = 0;
  if (sw <= 0) return;
  const double mx = sx / sw, my = sy / sw;
  const double a = sxx / sw - mx * mx, b = syy / sw - my * my, c = sxy / sw - mx * my;
  // The PSF sigma in pixels (the centroiders' unit); the elongation with y in units of a
  // pixel's width on the sky (binned rows are y_scale times taller), so that binned stars
  // are round.
  sigma = std::sqrt(std::max(0.5 * (a + b) - 1.0 / 12.0, 0.0));
  const double bs = b * y_scale * y_scale, cs = c * y_scale;
  const double tr = 0.5 * (a + bs);
  const double dd = std::sqrt(std::max(0.0, 0.25 * (a - bs) * (a - bs) + cs * cs));
  const double l1 = tr + dd, l2 = std::max(tr - dd, 1.0 / 12.0);
  elongation = std::sqrt(l1 / l2);
}

double Moments::minorVariance() const {
  if (sw <= 0) return 0;
  const Mat2 m = central();
  const double tr = 0.5 * (m(0, 0) + m(1, 1));
  const double dd = std::sqrt(std::max(0.0, 0.25 * (m(0, 0) - m(1, 1)) * (m(0, 0) - m(1, 1)) +
                                                 m(0, 1) * m(0, 1)));
  return std::max(tr - dd, 0.0);
}

// Largest of n pixel values: a plain max reduction, vectorised (unsigned integer max needs
// SSE4.1 or AVX2, hence the clones); the search windows of fast-moving stars are ~1000 pixels.
ST_AVX2_CLONES int maxOf(const uint8_t* p, int n) {
  uint8_t m = 0;
  for (int i = 0; i < n; ++i) m = std::max(m, p[i]);
  return m;
}
ST_AVX2_CLONES int maxOf(const uint16_t* p, int n) {
  uint16_t m = 0;
  for (int i = 0; i < n; ++i) m = std::max(m, p[i]);
  return m;
}

// Square root of the largest eigenvalue of the symmetric part of a 2x2 covariance.
double largestSigma(const Mat2& cov) {
  const double a = cov(0, 0), d = cov(1, 1), c = 0.5 * (cov(0, 1) + cov(1, 0));
  const double lmax = 0.5 * (a + d) + std::sqrt(0.25 * (a - d) * (a - d) + c * c);
  return std::sqrt(std::max(lmax, 0.0));
}

}  // namespace detect_detail

using namespace detect_detail;

int windowHalfSize(const PredictedStar& p, const DetectorOptions& opts) {
  const double sd = largestSigma(p.cov_px);
  const double psf = opts.psfSigmaGuess();
  const double h = opts.window_sigmas * sd + 3.0 * psf + 0.5 * p.blur_px.norm();
  if (!std::isfinite(h)) return opts.max_window_half_px;
  return std::clamp(static_cast<int>(std::ceil(h)), 2, opts.max_window_half_px);
}

// ---- StarDetector --------------------------------------------------------------------------

StarDetector::StarDetector(const DetectorOptions& opts)
    : StarDetector(opts, std::make_shared<Scratch>()) {}

StarDetector::StarDetector(const DetectorOptions& opts, std::shared_ptr<Scratch> scratch)
    : opts_(opts), scratch_(std::move(scratch)) {
  requireValid(opts_);
  k_ = opts_.threshold_mode == "dynamic"
           ? std::clamp(opts_.threshold_sigma, opts_.dynamic_min_sigma, opts_.dynamic_max_sigma)
           : opts_.threshold_sigma;
  main_ = Centroider::create(opts_.centroider);
  cog_ = Centroider::create("cog");
  ST_ASSERT(main_ && cog_ && scratch_);  // the name was validated; "cog" is in the table
}

std::unique_ptr<StarDetector> StarDetector::create(const DetectorOptions& opts, std::string* why) {
  if (!opts.isValid(why)) return nullptr;
  return std::make_unique<StarDetector>(opts);
}

namespace {
/// The grey view of `image` with the dark frame subtracted (saturating: never below 0), the
/// same for full frames and windows: a warm pixel is not a star in either.
bool darkSubtractedGrey(const cv::Mat& image, const DetectorOptions& opts, Scratch& s,
                        cv::Mat& grey, std::string& why) {
  if (!greyView(image, s.converted, grey, why)) return false;
  const cv::Mat& dark = opts.dark();
  if (dark.empty()) return true;
  if (dark.size() != grey.size() || dark.type() != grey.type()) {
    why = "dark frame size/type differs from the image";
    return false;
  }
  cv::subtract(grey, dark, s.dark_subtracted);
  grey = s.dark_subtracted;
  return true;
}
}  // namespace

StarDetector::~StarDetector() = default;
StarDetector::StarDetector(StarDetector&&) noexcept = default;
StarDetector& StarDetector::operator=(StarDetector&&) noexcept = default;

void StarDetector::detect(const cv::Mat& image, DetectionResult& res) {
  Scratch& s = *scratch_;
  cv::Mat grey;  // a header: the caller's pixels, or the scratch conversion of colour
  std::string why;
  if (!darkSubtractedGrey(image, opts_, s, grey, why)) {
    res = DetectionResult();
    res.reason = why;
    return;
  }
  if (opts_.threshold_mode != "dynamic") {
    detectFrame(grey, opts_, *main_, *cog_, s, res);
    res.threshold_sigma = opts_.threshold_sigma;
    return;
  }
  // The windows keep the configured k: only full frames use (and move) the dynamic one.
  const double fixed_k = opts_.threshold_sigma;
  opts_.threshold_sigma = k_;
  detectFrame(grey, opts_, *main_, *cog_, s, res);
  opts_.threshold_sigma = fixed_k;
  res.threshold_sigma = k_;
  // Seed 004 §8.2.3: sparse stars -> a lower threshold; many (noise spikes) -> a higher one.
  if (static_cast<int>(res.stars.size()) < opts_.dynamic_target_stars)
    k_ = std::max(opts_.dynamic_min_sigma, k_ - opts_.dynamic_step_sigma);
  else if (res.blobs_found > 2 * opts_.dynamic_target_stars)
    k_ = std::min(opts_.dynamic_max_sigma, k_ + opts_.dynamic_step_sigma);
}

DetectionResult StarDetector::detect(const cv::Mat& image) {
  DetectionResult res;
  detect(image, res);
  return res;
}

void StarDetector::centroidWindows(const cv::Mat& image,
                                   const std::vector<PredictedStar>& predicted,
                                   std::vector<WindowResult>& out) {
  Scratch& s = *scratch_;
  out.resize(predicted.size());
  for (WindowResult& w : out) {
    w.centroid.reset();
    w.reason.clear();  // keeps its capacity
  }
  cv::Mat grey;
  std::string why;
  if (!darkSubtractedGrey(image, opts_, s, grey, why)) {
    for (auto& w : out) w.reason = why;
    return;
  }
  const double sat = saturationLevel(grey, opts_);
  for (std::size_t i = 0; i < predicted.size(); ++i) {
    if (grey.depth() == CV_8U)
      centroidWindow<uint8_t>(grey, predicted[i], opts_, sat, *main_, *cog_, s, out[i]);
    else
      centroidWindow<uint16_t>(grey, predicted[i], opts_, sat, *main_, *cog_, s, out[i]);
  }
}

std::vector<WindowResult> StarDetector::centroidWindows(
    const cv::Mat& image, const std::vector<PredictedStar>& predicted) {
  std::vector<WindowResult> out;
  centroidWindows(image, predicted, out);
  return out;
}

// ---- the free functions: one detector per call ------------------------------------------

namespace {
// The one-shot detectors of this thread share their buffers, which so stay grown between
// calls (the free functions are not reentrant within a thread, and need not be).
StarDetector oneShot(const DetectorOptions& opts) {
  thread_local const std::shared_ptr<Scratch> scratch = std::make_shared<Scratch>();
  return StarDetector(opts, scratch);
}
}  // namespace

DetectionResult detectStars(const cv::Mat& image, const DetectorOptions& opts) {
  return oneShot(opts).detect(image);
}

std::vector<WindowResult> centroidWindows(const cv::Mat& image,
                                          const std::vector<PredictedStar>& predicted,
                                          const DetectorOptions& opts) {
  return oneShot(opts).centroidWindows(image, predicted);
}

}  // namespace st
