/// @file exposure.hpp
/// Exposure from the body rate (seed 004 sec. 4.2: "longer integration times require much
/// slower rotations to avoid stellar streaking"): the longest exposure whose smear, the
/// distance a star's image travels during it, stays under a set length anywhere on the
/// image, within the camera's exposure range. Longer exposures collect more light (SNR grows
/// as sqrt(t) for the background-limited star), so the longest allowed one is the choice.
#pragma once
#include "common/attitude.hpp"
#include "sensors/camera/camera_model.hpp"

namespace st {

/// [px/s] The fastest a star's image moves anywhere on the image for the angular rate
/// `omega_cam` [rad/s] (camera frame): rotation about the boresight moves the corners, about
/// a cross axis everything by ~f * |omega|, more off-axis. Through the camera model, so lens
/// distortion counts; sampled on a 9 x 9 grid over the image, corners included.
double maxImageSpeedPxPerS(const CameraModel& cam, const Vec3& omega_cam);

/// [s] The exposure for `omega_cam` whose smear stays under `max_smear_px`: max_smear_px /
/// maxImageSpeedPxPerS, clamped to [min_s, max_s] (at min_s a fast tumble still smears more:
/// the caller can see it with maxImageSpeedPxPerS * result).
double exposureForRate(const CameraModel& cam, const Vec3& omega_cam, double max_smear_px,
                       double min_s, double max_s);

}  // namespace st
