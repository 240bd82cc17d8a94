/// @file jacobians.hpp
/// Image-space Jacobians of the camera model, written once for every stage that turns an
/// attitude (or rate) uncertainty into pixels: the tracker's windows and gate, the pixel-space
/// attitude refinement, the streak lengths of a rotating camera.
#pragma once
#include <Eigen/Core>

#include "common/attitude.hpp"
#include "sensors/camera/camera_model.hpp"

namespace st {

using Mat23 = Eigen::Matrix<double, 2, 3>;

/// d(pixel)/d(v_cam) (2x3) of the camera projection at v_cam (z > 0).
Mat23 projectionJacobian(const CameraModel& cam, const Vec3& v_cam);

/// d(pixel)/d(dtheta) (2x3) of the image of direction v_cam under a small rotation dtheta of
/// the camera, with the error model R_true = R Exp(dtheta), so v_true = v + [v]x dtheta. The
/// same Jacobian maps a camera rate to the image velocity (v(tau) = v + [v]x omega tau), so
/// H omega T is a star's blur over an exposure T.
Mat23 attitudeJacobian(const CameraModel& cam, const Vec3& v_cam);

}  // namespace st
