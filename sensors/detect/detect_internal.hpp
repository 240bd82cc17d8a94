/// @file detect_internal.hpp
/// Internal to sensors/detect: what StarDetector's full-frame (detect_frame.cpp) and window
/// (detect_windows.cpp) paths share: the scratch buffers a detector owns, the grey view of an
/// input image, second moments, pixel patches and the centroid-with-fallback call.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "sensors/detect/background.hpp"
#include "sensors/detect/blob_labeller.hpp"
#include "sensors/detect/centroider.hpp"
#include "sensors/detect/detector_options.hpp"
#include "sensors/detect/star_detector.hpp"

namespace st::detect_detail {

struct Candidate {
  int blob;
  double sum;  ///< the ranking measure (larger first)
};

/// Per kept star of a full frame: whether its top is unclipped (its flux over peak is a
/// shape) and whether its peak is high enough for that ratio to set the frame's median; for a
/// clipped one, its pixels below half the clip, its clipped pixels and ln(clip / 2 threshold).
struct PeakShape {
  bool unclipped = false, sets_median = false;
  int wing_px = 0, clipped_px = 0;
  double wing_log = 0;
};

/// A detector's buffers, reused frame after frame: no allocation once they have grown to the
/// largest frame and window.
struct Scratch {
  BlobLabeller labeller;
  BackgroundModel background;
  std::vector<double> thresholds;  ///< per tile
  std::vector<Candidate> candidates;
  std::vector<PeakShape> peak_shapes;  ///< per kept star (detect_frame.cpp's flagDiffuse)
  std::vector<float> patch;  ///< values of the current centroid window
  std::vector<float> ring;   ///< border ring of the current search window
  cv::Mat converted;        ///< grey conversion of a colour input (never the caller's pixels)
  cv::Mat dark_subtracted;  ///< input minus the dark frame
  cv::Mat mask;             ///< candidate pixels for the pre-filters or a gradient
  cv::Mat threshold_map;    ///< per-pixel threshold of a background with a gradient
  /// [px] the PSF's three-pixel width along x and y the last full-frame detection measured
  /// (0 = unknown): what a tracking window's peak is tested against (radiation_hits.hpp)
  double frame_psf_x = 0, frame_psf_y = 0;
};

/// `grey`: a one-channel 8/16-bit view of the input, or of its conversion into `converted`
/// (colour only); false with a reason for an unusable image. `converted` is scratch and never
/// aliases the caller's pixels (a view stored there would be overwritten by the next colour
/// frame of the same size).
bool greyView(const cv::Mat& in, cv::Mat& converted, cv::Mat& grey, std::string& reason);

/// The saturation level: the option, else the largest value of the type that is a whole
/// number of quantisation steps `step` (12 bits in a 16-bit word clip at 65520, not 65535; an
/// 8-bit frame x256 at 65280).
inline double saturationLevel(const cv::Mat& grey, const DetectorOptions& opts, int step = 1) {
  if (opts.saturation_adu > 0) return opts.saturation_adu;
  const int top = grey.depth() == CV_8U ? 255 : 65535;
  return step > 1 ? top - top % step : top;
}

template <typename T>
double pix(const cv::Mat& m, int x, int y) {
  return static_cast<double>(m.ptr<T>(y)[x]);
}

/// Second moments of background-subtracted pixels, fed one at a time: elongation and a PSF
/// sigma estimate (the moments of a pixel-integrated Gaussian are s^2 + 1/12).
struct Moments {
  double sw = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  void add(int x, int y, double w) {
    if (w <= 0) return;
    sw += w;
    sx += w * x;
    sy += w * y;
    sxx += w * x * x;
    syy += w * y * y;
    sxy += w * x * y;
  }
  Mat2 central() const;
  /// sqrt(l1 / l2) of the central moments and the PSF sigma [px] they give; `y_scale` (the
  /// pixel aspect) stretches y first, so that binned rows' stars are round.
  void shape(double& elongation, double& sigma, double y_scale = 1) const;
  /// The smaller eigenvalue of the central moments [px^2] (0 without light).
  double minorVariance() const;
};

/// Largest of n pixel values (vectorised).
int maxOf(const uint8_t* p, int n);
int maxOf(const uint16_t* p, int n);

/// Square root of the largest eigenvalue of the symmetric part of a 2x2 covariance.
double largestSigma(const Mat2& cov);

/// A patch over `r` whose values live in `buf`: no allocation per star once the buffer has
/// grown to the largest window (valid until `buf` is next written).
template <typename T>
StarPatch makePatch(const cv::Mat& grey, const cv::Rect& r, double bg, double sigma_bg,
                    double sat, double psf, const Vec2& guess, const DetectorOptions& opts,
                    std::vector<float>& buf) {
  buf.resize(static_cast<std::size_t>(r.area()));
  float* out = buf.data();
  for (int y = r.y; y < r.y + r.height; ++y) {
    const T* row = grey.ptr<T>(y);
    for (int x = r.x; x < r.x + r.width; ++x) *out++ = static_cast<float>(row[x]);
  }
  StarPatch p;
  p.values = cv::Mat1f(r.height, r.width, buf.data());  // a header only
  p.origin = r.tl();
  p.background = bg;
  p.sigma_bg = sigma_bg;
  p.gain = opts.gain_e_per_adu;
  p.saturation = sat;
  p.psf_sigma = psf;
  p.guess = guess;
  p.reject_spikes = opts.reject_spikes;
  return p;
}

/// The configured centroider, with the plain CoG as the fallback when it fails.
inline bool measure(const Centroider& main, const Centroider& fallback, const StarPatch& p,
                    Centroid& c, std::string* reason) {
  if (main.centroid(p, c, reason)) return true;
  return &main != &fallback && fallback.centroid(p, c, reason);
}

/// Full-frame detection of `grey` (8/16-bit, one channel, dark frame already subtracted)
/// into `res` (every field reset; the star vector's capacity kept).
void detectFrame(const cv::Mat& grey, const DetectorOptions& opts, const Centroider& main,
                 const Centroider& cog, Scratch& s, DetectionResult& res);

/// One predictive window (seed 004 §4.2.3).
template <typename T>
void centroidWindow(const cv::Mat& grey, const PredictedStar& p, const DetectorOptions& opts,
                    double sat, const Centroider& main, const Centroider& cog, Scratch& s,
                    WindowResult& w);

}  // namespace st::detect_detail
