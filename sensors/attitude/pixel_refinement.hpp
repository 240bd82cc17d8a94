/// @file pixel_refinement.hpp
/// Attitude refinement in pixel space with each centroid's full 2x2 covariance. Wahba solvers
/// weigh every star with one isotropic sigma, but a streak's centroid error is several times
/// larger along the streak than across it, and all streaks of a frame are parallel: the
/// isotropic model misstates the attitude covariance (optimistic about the axis the streaks
/// move along). Gauss-Newton on the pixel residuals d_k = c_k - pi(R^T r_k) with their
/// covariances C_k, where pi(R Exp(dth)^T r) = pi(R^T r) + H_k dth (camera/jacobians.hpp):
///   dth = N^-1 sum H^T C^-1 d,  N = sum H^T C^-1 H,  covariance N^-1
/// (seed 004 eqs. 6.13 / 6.15 with the residuals in pixels: the inverse Fisher information).
/// A Wahba solution is the start; two steps converge. The residual statistic
/// sum d^T C^-1 d is then ~ chi2(2n - 3).
///
/// Frames: the attitude is the camera's, q_ic (v_i = R(q_ic) v_cam), its covariance in the
/// camera frame.
#pragma once
#include <string>
#include <vector>

#include "common/attitude.hpp"
#include "sensors/camera/camera_model.hpp"

namespace st {

/// One matched star: the measured centroid and the catalog direction.
struct PixelObservation {
  Vec2 px = Vec2::Zero();      ///< [px] measured centroid
  Mat2 cov_px = Mat2::Zero();  ///< [px^2] its covariance (floored by the caller's floor_px)
  Vec3 r_i = Vec3::UnitZ();    ///< catalog unit vector, inertial frame
};

struct PixelRefinement {
  bool ok = false;
  std::string reason;            ///< why not ok
  Quat q_ic = Quat::Identity();  ///< refined camera attitude (canonical)
  Mat3 cov_cam = Mat3::Zero();   ///< [rad^2] camera-frame covariance, N^-1
  double chi2 = 0;               ///< sum of the normalised squared residuals at q_ic
};

/// Refines `q_ic` over `obs`, each centroid covariance plus floor_px^2 I. `e2` receives each
/// star's normalised squared residual at the result (resized to obs.size(); a caller's
/// buffer, so that no frame allocates).
PixelRefinement refineInPixels(const CameraModel& camera, const std::vector<PixelObservation>& obs,
                               const Quat& q_ic, double floor_px, std::vector<double>& e2);

}  // namespace st
