/// @file observer_aberration.hpp
/// The aberration of the observer's own velocity (seed 003 "Aberration", item 3: a low orbit's
/// 7.5-8.3 km/s moves every star up to 5.2-5.7" towards the apex). The star database holds
/// directions aberrated for the Earth's orbit at its epoch (catalog/epoch_correction.hpp); an
/// orbiting camera sees them aberrated once more by its velocity relative to the Earth. Left
/// alone this is a rotation of the fix by up to |v|/c about (boresight x v): an attitude error
/// the covariance knows nothing of.
///
/// Two ways the tracker applies it, both exact to O((v/c)^2) = 1e-9 rad:
///  - tracking solves against the apparent directions themselves (applyAberration), so the
///    pixel refinement, the consistency check against the prediction and the online camera
///    fit all see the sky as the camera does;
///  - a lost-in-space fix, identified and verified against the database's directions, is
///    turned afterwards by the small rotation that best carries its stars' apparent
///    directions onto the database's (correctForAberration).
#pragma once
#include <vector>

#include "common/aberration.hpp"

namespace st {

/// q_ic solved against the database directions `u_i` (weights `w`, e.g. 1/sigma^2) -> the
/// attitude against their apparent directions for `velocity_km_s`. With R_g u ~ v_cam and
/// f(u) = R_true v_cam: R_true = R_E^T R_g, R_E the least-squares rotation with u ~ R_E f(u),
/// to first order phi = (sum w (I - u u^T))^-1 sum w (f(u) - u) x u. Needs two stars that are
/// not parallel; returns q_ic unchanged otherwise.
Quat correctForAberration(const Quat& q_ic, const std::vector<Vec3>& u_i,
                          const std::vector<double>& w, const Vec3& velocity_km_s);

}  // namespace st
