/// @file centroider.hpp
/// The family of centroiders: given a small window of pixels around one star and the noise
/// model, estimate the position with its covariance, the flux and the SNR.
///   "cog"   intensity-weighted centre of gravity, background removed (seed 004 eq. 4.1/4.23)
///   "iwc"   iterative weighted centroid: CoG with a Gaussian weight re-centred until fixed
///   "gauss" maximum-likelihood fit of the pixel-integrated Gaussian PSF (seed 004 §4.2.2)
/// Implementers override doCentroid(); names and help come from the one registry table in
/// centroider_registry.cpp. A new centroider is its own file defining
/// `std::unique_ptr<Centroider> makeXCentroider()` in namespace st plus one line in that table
/// (or one ST_REGISTER_FAMILY_MEMBER line for a centroider compiled into an executable,
/// common/family_registry.hpp); tests/detect's accuracy suite runs over every registered name.
/// Centroiders are stateless (centroid() is const and thread-safe).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "sensors/detect/centroid.hpp"

namespace st {

/// Pixels around one star and what is known about the noise there.
struct StarPatch {
  cv::Mat1f values;          ///< [ADU] raw pixel values (background not removed)
  cv::Point origin{0, 0};    ///< image coordinates of values(0, 0)
  double background = 0;     ///< [ADU] local background level
  double sigma_bg = 1;       ///< [ADU] per-pixel noise without star light
  /// [ADU^2] variance of `background` itself (an estimate from a few pixels): it moves every
  /// background-subtracted pixel of the window together, so centroiders that take the
  /// background as given add its effect on the position to the covariance.
  double background_var = 0;
  double gain = 1;           ///< [e-/ADU]
  double saturation = 1e30;  ///< [ADU] pixels at or above are excluded where possible
  double psf_sigma = 1;      ///< [px] PSF sigma guess (> 0)
  /// [px] image coordinates of a first position (the centre of light above the threshold, or
  /// the peak)
  Vec2 guess = Vec2::Zero();
  /// [px] motion of the star during the exposure when known (tracking: from the gyro rate),
  /// else zero. A model-fitting centroider whose PSF is round widens the covariance along it.
  Vec2 smear = Vec2::Zero();
  bool reject_spikes = false;  ///< a model fit may drop single-pixel outliers (hot pixels)

  /// Variance [ADU^2] of a pixel whose background-subtracted expected signal is `s`.
  double variance(double s) const { return sigma_bg * sigma_bg + (s > 0 ? s / gain : 0.0); }
};

class Centroider {
 public:
  virtual ~Centroider() = default;
  /// Fills px, cov_px, flux, peak, snr of `out` (area and flags are the caller's). Returns
  /// false with a reason when the star cannot be measured (no flux, fit diverged, ...).
  bool centroid(const StarPatch& patch, Centroid& out, std::string* reason = nullptr) const;
  virtual std::string name() const = 0;

  /// nullptr with a message listing the valid names if `name` is unknown.
  static std::unique_ptr<Centroider> create(const std::string& name, std::string* error = nullptr);
  static std::vector<std::string> names();
  static std::string help();  ///< one line per centroider

  using Make = std::unique_ptr<Centroider>();  ///< a member's factory (function type)
  using Factory = Make*;
  /// Runtime hook behind ST_REGISTER_FAMILY_MEMBER (common/family_registry.hpp).
  static void registerMember(const std::string& name, const std::string& help, Factory make);

 private:
  virtual bool doCentroid(const StarPatch& patch, Centroid& out, std::string* reason) const = 0;
};

}  // namespace st
