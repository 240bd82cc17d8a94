/// @file star_renderer.hpp
/// Renders the sky's signal onto the detector: for every catalog star in the field of view
/// (and every non-catalog source such as a planet or an extended object), its electrons from
/// its magnitude (SensorParams::starElectrons, seed 004 eq. 3.4), spread by the Gaussian PSF
/// integrated over each pixel (psf.hpp), along the path the star takes across the detector
/// during the exposure (motion blur), projected through the camera model (lens distortion
/// included). The result is an image of MEAN signal electrons; the Detector adds background
/// and noise and digitises it.
///
/// Motion blur: the exposure [-T/2, T/2] around the frame time is cut into N equal
/// sub-intervals and the star's light is split equally among the PSFs at their mid-times.
/// N is chosen per frame so that consecutive sub-steps are at most 0.5 PSF sigma apart along
/// the longest streak. Along the streak the ripple of a row of Gaussians spaced d apart,
/// relative to a continuous streak, is 2 exp(-2 pi^2 sigma^2 / d^2) = 2 exp(-79): none. The
/// streak's two ends carry the midpoint rule's error, ~ (d / sigma)^2 / 24 of the peak before
/// pixel integration; tests/sim measures 2e-3 of the peak pixel at d = 0.5 sigma, below the
/// shot noise of any unsaturated pixel (1 / sqrt(full well) = 7e-3 at 20 ke-).
///
/// Not thread-safe (scratch buffers); use one renderer per thread.
#pragma once
#include <functional>
#include <opencv2/core.hpp>
#include <vector>

#include "common/attitude.hpp"
#include "sensors/camera/camera_model.hpp"
#include "sensors/sim/sensor_params.hpp"
#include "sensors/sim/star_source.hpp"

namespace st {

/// q_ib at time offset `tau` [s] from mid-exposure.
using AttitudeAt = std::function<Quat(double tau)>;
/// Constant body rate over the exposure: q(tau) = q_mid (x) Exp(omega_body tau).
AttitudeAt constantRateAttitude(const Quat& q_mid_ib, const Vec3& omega_body);

/// A star as it truly appears in a frame (ground truth).
struct TrueStar {
  uint32_t id;       ///< catalog id
  Vec2 px;           ///< [px] position at mid-exposure
  double mag;        ///< V magnitude
  double electrons;  ///< total signal electrons (eq. 3.4), before any clipping
};

/// A light source that is not a catalog star: fixed in the inertial frame, not in the truth.
struct ExtraSource {
  Vec3 u_i;
  double mag;
  double sigma_px;  ///< PSF sigma for this source (the optics' for a planet, larger for an
                    ///< extended object)
};

struct RenderOptions {
  std::vector<ExtraSource> extras;
  double missing_star_fraction = 0;  ///< drop this fraction of catalog stars (by id, stable)
  uint64_t missing_star_seed = 0;
  double max_substep_sigma = 0.5;    ///< sub-step spacing along a streak, in PSF sigmas
  int max_substeps = 4096;
  /// [s] this frame's exposure when it is not the sensor's (SensorParams::max_smear_px): the
  /// streaks span it and the stars' electrons scale with it; 0 = sensor().exposure_s.
  double exposure_s = 0;
  /// [km/s] the observer's velocity relative to the star directions' observer (an orbit's,
  /// orbit.hpp): every source is drawn at its aberrated direction (common/aberration.hpp).
  Vec3 observer_velocity_km_s = Vec3::Zero();
};

class StarRenderer {
 public:
  /// `stars` must outlive the renderer.
  StarRenderer(const CameraModel& camera, const SensorParams& sensor, const StarSource& stars);

  /// Adds the signal electrons of one exposure to `electrons` (CV_64F, camera size, e.g. a
  /// copy of Detector::meanBackground(), or zeros) and returns the rendered catalog stars
  /// whose mid-exposure position lies in the image (the ground truth), brightest first.
  std::vector<TrueStar> render(const AttitudeAt& q_ib_at, cv::Mat& electrons,
                               const RenderOptions& opts = {}) const;

  /// Whether the catalog star `id` is one of the dropped ones for these options.
  static bool isMissing(uint32_t id, const RenderOptions& opts);

  const CameraModel& camera() const { return cam_; }
  const SensorParams& sensor() const { return sensor_; }
  /// Number of blur sub-steps used by the last render() call (for tests and benchmarks).
  int lastSubsteps() const { return last_substeps_; }

 private:
  CameraModel cam_;
  SensorParams sensor_;
  const StarSource& stars_;
  mutable std::vector<SkyStar> scratch_;
  mutable int last_substeps_ = 0;
};

}  // namespace st
