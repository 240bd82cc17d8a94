/// @file camera_fit.hpp
/// The project's one camera-model fit: intrinsics (focal length, principal point, radial
/// distortion k1, k2) estimated from identified stars, with each frame's attitude a nuisance
/// parameter. Stars are perfect calibration targets: their directions are known to
/// milliarcseconds, so the pixel residuals are the camera model's error plus centroid noise.
///
/// Used by the plate solver (focal length and distortion from the sky, self-healing of an
/// approximate camera file), by `startracker calibrate` (many frames) and by the star tracker
/// online (one frame at a time: the posterior of one fit is the prior of the next, a
/// recursive information filter over the intrinsics).
///
/// Model: the measured centroid p_k of star k in frame j is
///     p_k = project(theta, R_ic(j)^T u_k) + e_k,   e_k ~ N(0, sigma_k^2 I2)
/// (project = CameraModel::vectorToPixel with intrinsics theta). Least squares over theta and
/// the frames' rotations (q_ic(j) <- q_ic(j) * Exp(dphi_j)) by Levenberg-Marquardt with a
/// Gaussian prior on theta; the covariance of theta is the inverse of the Gauss-Newton
/// information at the solution with the attitudes marginalised (the full inverse's block).
/// A shift of the principal point is almost a rotation of a narrow field: with one frame its
/// uncertainty is large and a prior keeps the problem well posed.
#pragma once
#include <string>
#include <vector>

#include <Eigen/Core>

#include "sensors/camera/camera_model.hpp"

namespace st {

/// The five intrinsics a fit may estimate, in this order.
enum CameraParam { kFx = 0, kFy, kCx, kCy, kK1, kK2, kNumCameraParams };
using CameraParams = Eigen::Matrix<double, kNumCameraParams, 1>;
using CameraParamsCov = Eigen::Matrix<double, kNumCameraParams, kNumCameraParams>;

/// fx fy cx cy k1 k2 of a camera, and the camera with them (the other distortion terms
/// p1 p2 k3 and the image size are taken from `base`).
CameraParams cameraParams(const CameraModel& cam);
CameraModel withCameraParams(const CameraModel& base, const CameraParams& theta);

/// Which intrinsics are free; the rest keep the start camera's values.
struct CameraFitSpec {
  bool focal = true;             ///< fx and fy, their ratio kept (square pixels stay square)
  bool aspect = false;           ///< fx and fy independently (needs focal)
  bool principal_point = false;  ///< cx, cy
  int radial_terms = 0;          ///< 0, 1 (k1) or 2 (k1, k2)
};

/// Gaussian prior on the intrinsics: mean and information (inverse covariance). A zero
/// information row leaves that parameter free.
struct CameraPrior {
  CameraParams mean = CameraParams::Zero();
  CameraParamsCov information = CameraParamsCov::Zero();
  /// A camera file's values, trusted to the given 1-sigma (relative focal length, principal
  /// point [px], k1 and k2): the prior of the self-healing fits.
  static CameraPrior around(const CameraModel& cam, double sigma_focal_rel, double sigma_pp_px,
                            double sigma_k);
};

/// The stars identified in one frame: measured pixels, catalog (inertial) directions, pixel
/// sigmas, and the frame's attitude (the fit's starting point).
struct FrameStars {
  std::vector<Vec2> px;
  std::vector<Vec3> u_i;
  std::vector<double> sigma_px;
  Quat q_ic = Quat::Identity();
  void add(const Vec2& p, const Vec3& u, double sigma) {
    px.push_back(p), u_i.push_back(u), sigma_px.push_back(sigma);
  }
  std::size_t size() const { return px.size(); }
};

struct CameraFitOptions {
  int max_iterations = 50;
  /// Stars whose normalised residual exceeds this after convergence are dropped and the fit
  /// repeated (a few rounds); 0 keeps every star.
  double outlier_sigma = 0;
};

struct CameraFitResult {
  bool ok = false;
  std::string reason;                ///< why not ok
  CameraModel camera;                ///< the fitted camera
  std::vector<Quat> q_ic;            ///< refined attitude of every frame
  CameraParams theta = CameraParams::Zero();
  CameraParamsCov cov = CameraParamsCov::Zero();  ///< zero rows for fixed parameters
  CameraFitSpec spec;
  double chi2 = 0;                   ///< of the residuals (prior excluded)
  int dof = 0;                       ///< 2 n_stars - free parameters
  int stars = 0;                     ///< stars used (outliers excluded)
  int outliers = 0;
  std::vector<std::vector<char>> used;  ///< per frame and star: 0 for an excluded outlier
  double rms_before_px = 0, rms_after_px = 0;  ///< over all stars used
  std::vector<double> frame_rms_before_px, frame_rms_after_px;
  int iterations = 0;

  double sigma(CameraParam p) const { return std::sqrt(std::max(0.0, cov(p, p))); }
  /// The posterior as the prior of the next fit (online refinement).
  CameraPrior posterior() const;
};

/// Fits `spec`'s intrinsics and every frame's attitude, starting from `start` and the frames'
/// q_ic. `prior` may be null. Never throws on bad data: a fit that cannot be made (too few
/// stars for the free parameters, a singular problem, a camera that stops being valid) is
/// !ok with a reason.
CameraFitResult fitCamera(const CameraModel& start, const std::vector<FrameStars>& frames,
                          const CameraFitSpec& spec, const CameraPrior* prior = nullptr,
                          const CameraFitOptions& options = {});

/// fitCamera with the number of radial terms the stars support, up to spec.radial_terms:
/// a term is kept only when it lowers chi2 by more than the 1-dof chi-square quantile at
/// `alpha` (a likelihood-ratio test, nested models).
CameraFitResult fitCameraChoosingRadial(const CameraModel& start,
                                        const std::vector<FrameStars>& frames,
                                        const CameraFitSpec& spec,
                                        const CameraPrior* prior = nullptr,
                                        const CameraFitOptions& options = {},
                                        double alpha = 1e-3);

/// The extra per-axis pixel sigma s that makes the residuals consistent with their sigmas:
/// chi2 with sigma_k^2 + s^2 equals dof (0 when chi2 <= dof already). The camera-model error
/// term: what the model leaves unexplained, beyond centroid noise.
double modelErrorSigmaPx(const CameraFitResult& fit, const std::vector<FrameStars>& frames);

/// Human-readable discrepancy of a fitted camera against a reference (a camera file):
/// "focal length 0.10 % longer than camera.yaml (+-0.01 %)", empty when nothing differs by
/// more than `n_sigma` of the fit's uncertainty.
std::string describeDiscrepancy(const CameraFitResult& fit, const CameraModel& reference,
                                const std::string& reference_name, double n_sigma = 3.0);

}  // namespace st
