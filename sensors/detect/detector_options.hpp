/// @file detector_options.hpp
/// Settings of star detection and centroiding (star_detector.hpp), with their defaults and
/// why. Noise model (ADU): a pixel with background-subtracted signal S has variance
///   var = sigma_bg^2 + max(S, 0) / gain
/// where sigma_bg (read noise + sky shot noise + quantisation) is measured from the image
/// (median absolute deviation) and never taken below read_noise_adu.
#pragma once
#include <cstdint>
#include <string>

#include <opencv2/core.hpp>

#include "sensors/detect/centroid.hpp"

namespace st {

/// A master dark named by a file (`startracker dark`): the ini key detect_dark_file reads
/// the file into `image` when the configuration is read, so a bad file fails there (exit 2)
/// and not at the first frame; `path` is what the printed configuration shows.
struct DarkFrameFile {
  std::string path;  ///< "" = none
  cv::Mat image;
};

struct DetectorOptions {
  // --- noise model ---
  double gain_e_per_adu = 1.0;  ///< [e-/ADU] converts signal to shot-noise variance
  double read_noise_adu = 0.0;  ///< [ADU] floor for the measured background sigma
  double saturation_adu = 0.0;  ///< [ADU] pixel >= this is saturated; 0 = max of the type

  // --- background and threshold (seed 004 §4.1) ---
  double threshold_sigma = 5.0;  ///< k: a pixel is a candidate if value > background + k*sigma
  /// Dynamic thresholding (seed 004 §8.2.3: "automatically set the noise threshold level
  /// based on the properties of the recent images"): "fixed" keeps threshold_sigma; "dynamic"
  /// starts there and, after each full-frame detection, lowers k by dynamic_step_sigma when
  /// fewer than dynamic_target_stars stars were kept ("sparse numbers of stars": dig out
  /// fainter ones) and raises it when the blobs above the threshold exceed twice that
  /// ("eliminate potential noise spikes"), within [dynamic_min_sigma, dynamic_max_sigma].
  /// The per-tile level and sigma already make k local in space; this makes it follow the
  /// sky from frame to frame. Windows of tracking keep threshold_sigma.
  std::string threshold_mode = "fixed";
  int dynamic_target_stars = 20;
  double dynamic_min_sigma = 3.0;   ///< below it noise blobs outnumber faint stars (seed Fig. 4.1: k = 1 passes 10 % of pixels)
  double dynamic_max_sigma = 10.0;
  double dynamic_step_sigma = 0.5;
  int background_tile_px = 128;  ///< tile side for the tiled median/MAD; 0 = one global value
  int background_samples = 256;  ///< pixels sampled per tile (or globally x16): speed vs noise
  cv::Mat dark_frame;            ///< optional dark frame, same size and type, subtracted first
  DarkFrameFile dark_file;       ///< the dark of the ini key; used when dark_frame is empty
  /// The dark subtracted: dark_frame when set in code, else the ini key's.
  const cv::Mat& dark() const { return dark_frame.empty() ? dark_file.image : dark_frame; }

  /// Pre-filter of seed 004 §4.1 / §4.2.2, meant for low thresholds (k ~ 1-2):
  ///   "none"; "neighbourhood": keep a candidate pixel if >= prefilter_min_count of the 5x5
  ///   pixels centred on it are candidates (starCentroid2); "grid": the same count on a fixed
  ///   5x5 grid of cells, keeping pixels of passing cells and their 8 neighbour cells
  ///   (starCentroid3, cheaper when many pixels pass the threshold).
  std::string prefilter = "none";
  int prefilter_min_count = 9;  ///< of 25 (seed 004 §4.1: "at least 9 of the 25")

  // --- blobs ---
  /// [px] smaller blobs are noise spikes. Seed 004 §4.1 drops < 3 px at a threshold near
  /// SNR 1; at k = 5 single pixels are the risk (hot pixels, cosmics), while faint stars of a
  /// sharp PSF (the tetra3 frames) cover only 2-3 pixels.
  int min_area = 2;
  int max_area = 2000;          ///< [px] larger blobs are the Moon, planets, glare
  int max_stars = 100;          ///< keep the brightest this many
  double min_separation_px = 3.0;  ///< a centroid closer to a brighter one is the same star
  double max_elongation = 2.5;  ///< sqrt(lambda1/lambda2) of second moments above: kElongated
  /// A pixel's height over its width on the sky (the camera's fx / fy; 2 for rows binned 2x):
  /// blob shapes are judged with y stretched by it, so that a binned frame's round stars are
  /// not elongated. The star tracker sets it from its camera, solve from the camera search.
  double pixel_aspect = 1;
  /// peak / (3x3 flux above background) above this: kHotPixel. A Gaussian PSF of sigma
  /// >= 0.5 px puts at most 47% of its 3x3 light in one pixel; noise in the neighbours pulls a
  /// real hot pixel's ratio down to ~0.7 at 5 sigma.
  double hot_pixel_fraction = 0.7;
  /// [px] kExtended above this sigma of a blob's light across its narrow axis (the smaller
  /// eigenvalue of its second moments, less what a saturated core explains): a star, in
  /// focus or a streak, is one PSF wide; a lit foreground, the skyline's edge, a glow, a
  /// cloud's rim are wider. Stars up to a PSF sigma of about this pass (the window of the
  /// centroiders stops at 5 px).
  double max_psf_sigma_px = 4.0;
  /// Flags that remove a star instead of only marking it. Elongated is off by default since
  /// stars are streaks by design during slews.
  uint32_t reject_flags = kHotPixel | kTouchesEdge | kExtended;
  /// Radiation hits (kRadiationHit, full-frame detection): a blob sharper than this frame's
  /// stars along some direction (its peak over its neighbours beyond what the PSF measured on
  /// the frame's star-like blobs allows) is charge deposited by a particle, not light through
  /// the optics. Flagged hits are kept but ranked after every star (lost-in-space never builds
  /// a pattern on one; see radiation_hits.hpp); false turns the rule off.
  bool flag_hits = true;

  // --- centroiding ---
  std::string centroider = "gauss";  ///< "cog", "iwc" or "gauss" (see centroider.hpp)
  double psf_sigma_px = 0.0;  ///< [px] PSF sigma guess; 0 = estimate per star from moments
  /// [px] the PSF sigma assumed when psf_sigma_px is 0 and a star's moments do not tell it
  /// (one number for the detector, the streak code and the replay's scoring).
  static constexpr double kAssumedPsfSigmaPx = 1.2;
  /// psf_sigma_px when given, else kAssumedPsfSigmaPx: for what needs one number per frame.
  double psfSigmaGuess() const { return psf_sigma_px > 0 ? psf_sigma_px : kAssumedPsfSigmaPx; }
  int window_margin_px = 2;   ///< [px] added around a blob's box for the centroid window
  /// "gauss": drop single-pixel spikes far above the fitted PSF (hot pixels, cosmic rays on
  /// a star's wing) and fit again; see gauss_fit.cpp. Off by default: it needs saturation_adu
  /// right (a star clipped below the assumed level has a top that looks like spikes).
  bool reject_spikes = false;

  // --- predictive windows (seed 004 §4.2.3) ---
  double window_sigmas = 3.0;  ///< half-size = window_sigmas*sqrt(max eig cov) + PSF radius
  int max_window_half_px = 40;  ///< cap on the half-size of a predictive window

  /// True when all values are usable; otherwise false with a message naming the field.
  bool isValid(std::string* error = nullptr) const;
};

}  // namespace st
