/// @file star_observation.hpp
/// A detected star as identification and attitude estimation see it: a unit vector in the
/// camera frame with an isotropic 1-sigma angular error, its pixel and its brightness.
#pragma once
#include <vector>

#include "common/attitude.hpp"
#include "sensors/camera/camera_model.hpp"
#include "sensors/detect/centroid.hpp"

namespace st {

struct StarObservation {
  Vec3 v_cam = Vec3::UnitZ();  ///< unit vector, camera frame
  double sigma = 0;            ///< [rad] 1-sigma per axis of the direction error (isotropic)
  Vec2 px = Vec2::Zero();      ///< [px] centroid
  double brightness = 0;       ///< flux [ADU] (only the order matters)
};

/// The largest centroid-sigma floor taken [px] (solve --min-sigma-px, the tracker's
/// min_sigma_px): a pair tolerance of several sigma that wide admits so many catalog pairs that
/// no pattern is unique (3 px fails on every tetra3 frame, 10 px takes seconds, 30 px did not
/// end: issue 39); a centroid worse than 2 px is no star.
constexpr double kMaxCentroidSigmaFloorPx = 2.0;

/// Centroids -> camera-frame unit vectors. The pixel covariance is mapped to the tangent
/// plane of the unit sphere through the inverse pixel Jacobian (CameraModel::pixelJacobian)
/// and the derivative of p/|p|, p = (x, y, 1); `sigma` is the RMS per axis sqrt(trace/2) of
/// that 2x2 angular covariance, floored at `min_sigma_px` pixels (a centroid is never
/// perfect: a zero covariance would give a star infinite weight). `model_error_px`, the
/// camera model's own error (camera_fit.hpp modelErrorSigmaPx), adds in quadrature before
/// the floor. Order is kept.
std::vector<StarObservation> toStarObservations(const std::vector<Centroid>& centroids,
                                                const CameraModel& camera,
                                                double min_sigma_px = 0.02,
                                                double model_error_px = 0);

}  // namespace st
