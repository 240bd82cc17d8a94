/// @file star_detector.hpp
/// Star detection and centroiding (seed 004 ch. 4): background and noise, threshold at
/// k sigma, optional pre-filter, blobs (8-connected), per-star centroid with covariance.
///   StarDetector::detect           full frame, when lost (lost-in-space);
///   StarDetector::centroidWindows  only small windows around predicted stars, when tracking
///                                  (§4.2.3).
/// Input: 8- or 16-bit grey cv::Mat (colour is converted to grey; MRPT's CImage through
/// sensors/mrpt/image_detect.hpp). Bad images give an empty result with a reason.
/// Options are validated once, when the StarDetector is built; the free functions
/// detectStars / centroidWindows are convenience wrappers that build one per call (and so
/// validate, throwing InputError naming the field, and allocate every time): per-frame code
/// keeps a StarDetector.
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "sensors/detect/centroid.hpp"
#include "sensors/detect/detector_options.hpp"

namespace st {

class Centroider;
namespace detect_detail {
struct Scratch;
}

struct DetectionResult {
  std::vector<Centroid> stars;  ///< brightest first, at most opts.max_stars
  std::string reason;           ///< empty = ok; otherwise why there are no stars
  double background = 0;        ///< [ADU] global background level
  double noise_sigma = 0;       ///< [ADU] global background noise
  int blobs_found = 0;          ///< connected components above the threshold
  int rejected = 0;             ///< blobs dropped (area, reject_flags, failed centroid)
  int duplicates = 0;           ///< centroids dropped as the same star as a brighter one
  double threshold_sigma = 0;   ///< k of this detection (threshold_mode dynamic: it varies)
  int hits = 0;                 ///< stars flagged kRadiationHit (kept, ranked last)
  /// [px] the frame's PSF along columns (x) and rows (y): the three-pixel Gaussian width
  /// of its most significant unclipped blobs (their widest tight cluster) (radiation_hits.hpp; 0 when too few
  /// tell), what the hit rule compares with
  double psf_width_x = 0, psf_width_y = 0;
  /// The blobs the filters dropped (area, reject_flags, no centroid), for pictures of why a
  /// frame failed: where, how large, which flags (0 when none explains it).
  struct Rejected {
    Vec2 px = Vec2::Zero();
    int area = 0;
    uint32_t flags = 0;
  };
  std::vector<Rejected> rejected_blobs;
};


/// A star expected on the image: where, how sure (covariance), and the streak its image
/// draws during the exposure (blur vector, from the body rate).
struct PredictedStar {
  Vec2 px = Vec2::Zero();
  Mat2 cov_px = Mat2::Identity();
  Vec2 blur_px = Vec2::Zero();
  /// The streak's middle is searched around `px` (a point known to lie on this star's
  /// streak, e.g. a fragment found by full-frame detection) instead of around the brightest
  /// pixel of the window, which may belong to another star.
  bool anchor_at_px = false;
};
/// One per predicted star: the centroid or why not ("outside image", "below threshold",
/// "not found: ...").
struct WindowResult {
  std::optional<Centroid> centroid;
  std::string reason;
};

/// Half-size [px] of the search window of a predicted star: window_sigmas * sqrt(largest
/// eigenvalue of cov) + PSF radius (3 sigma) + half the blur length, capped.
int windowHalfSize(const PredictedStar& p, const DetectorOptions& opts);

/// Detection with options validated once. Owns its centroiders and scratch buffers, so the
/// per-frame calls validate nothing, throw nothing (bad images give a reason) and, once the
/// buffers have grown to the largest frame, allocate only what they return.
/// Not thread-safe (the scratch buffers): one detector per thread.
class StarDetector {
 public:
  /// Throws InputError naming the field when `opts` is invalid (the construction edge).
  explicit StarDetector(const DetectorOptions& opts);
  /// The same without throwing: nullptr and *why for invalid options.
  static std::unique_ptr<StarDetector> create(const DetectorOptions& opts, std::string* why);
  /// Like the first, with scratch buffers shared with other detectors of this thread (the
  /// free functions' one-shot detectors keep their buffers warm this way). Detectors sharing
  /// scratch must not run concurrently.
  StarDetector(const DetectorOptions& opts, std::shared_ptr<detect_detail::Scratch> scratch);
  ~StarDetector();
  StarDetector(StarDetector&&) noexcept;
  StarDetector& operator=(StarDetector&&) noexcept;

  const DetectorOptions& options() const { return opts_; }
  /// The k the next full-frame detection uses (threshold_sigma unless threshold_mode is
  /// "dynamic").
  double thresholdSigma() const { return k_; }

  /// Full frame: stars brightest first (at most options().max_stars).
  DetectionResult detect(const cv::Mat& image);
  /// The same into `out`, whose star vector keeps its capacity from frame to frame.
  void detect(const cv::Mat& image, DetectionResult& out);

  /// Only the windows (background from each window's border); `out` gets one result per
  /// predicted star, its capacity reused between calls.
  void centroidWindows(const cv::Mat& image, const std::vector<PredictedStar>& predicted,
                       std::vector<WindowResult>& out);
  std::vector<WindowResult> centroidWindows(const cv::Mat& image,
                                            const std::vector<PredictedStar>& predicted);

 private:
  DetectorOptions opts_;
  double k_ = 0;  ///< full-frame threshold [sigma]; moves between frames when dynamic
  std::unique_ptr<Centroider> main_;  ///< opts_.centroider
  std::unique_ptr<Centroider> cog_;   ///< fallback when main_ fails, and for streaks
  std::shared_ptr<detect_detail::Scratch> scratch_;
};

/// Convenience wrappers: one StarDetector per call (validates, may throw InputError).
DetectionResult detectStars(const cv::Mat& image, const DetectorOptions& opts = {});

/// Reads only the windows (background from each window's border).
std::vector<WindowResult> centroidWindows(const cv::Mat& image,
                                          const std::vector<PredictedStar>& predicted,
                                          const DetectorOptions& opts = {});

}  // namespace st
