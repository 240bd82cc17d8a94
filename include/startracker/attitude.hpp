/// @file attitude.hpp
/// Attitude maths on Eigen types, following common/conventions.hpp: quaternion helpers,
/// SO(3) exp/log, unit vectors from RA/Dec, RA/Dec/roll of the boresight and the
/// attitude-error metrics (total, cross-boresight, roll).
#pragma once
#include <Eigen/Core>
#include <cmath>
#include <Eigen/Geometry>

namespace st {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat2 = Eigen::Matrix2d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

/// The quaternion with w >= 0 (q and -q are the same rotation), normalised.
Quat canonical(const Quat& q);

/// Skew-symmetric matrix [v]x such that [v]x * u = v x u.
Mat3 skew(const Vec3& v);

/// Rotation by the rotation vector `rotvec` (axis * angle), exact for any angle.
Quat quatExp(const Vec3& rotvec);
/// Rotation vector of q (angle in [0, pi]); inverse of quatExp for canonical q.
Vec3 quatLog(const Quat& q);

/// [rad] angle between two directions (not necessarily unit): atan2(|a x b|, a.b), accurate at
/// the small angles of star pairs where acos(a.b) loses half its digits.
inline double angleBetween(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

/// Unit vector of a direction given by right ascension and declination [rad].
Vec3 unitVectorFromRaDec(double ra, double dec);
/// Right ascension in [0, 2pi) and declination in [-pi/2, pi/2] of a (not necessarily unit) vector.
void raDecFromVector(const Vec3& v, double& ra, double& dec);

/// Boresight direction and roll of an attitude, in radians (see conventions.hpp).
struct RaDecRoll {
  double ra = 0;    ///< [rad] in [0, 2pi)
  double dec = 0;   ///< [rad]
  double roll = 0;  ///< [rad] in (-pi, pi]
};
/// q_ib from boresight RA/Dec and roll: R_ib = [-east | -north | boresight] * Rz(roll).
Quat attitudeFromRaDecRoll(const RaDecRoll& rdr);
/// Inverse of attitudeFromRaDecRoll. At the celestial poles RA is 0 by convention and the
/// roll absorbs the rest.
RaDecRoll raDecRollFromAttitude(const Quat& q_ib);

/// Error of an attitude estimate against truth (see conventions.hpp), radians.
struct AttitudeError {
  double total = 0;            ///< angle of R_est^T R_true, [0, pi]
  double cross_boresight = 0;  ///< angle between the two boresights (swing), [0, pi]
  double roll = 0;             ///< signed twist about the boresight, (-pi, pi]
  Vec3 rotvec_body = Vec3::Zero();  ///< Log(R_est^T R_true): the body-frame error vector
};
AttitudeError attitudeError(const Quat& q_ib_est, const Quat& q_ib_true);

/// Normalised estimation error squared of an attitude estimate against truth with its
/// 3x3 body-frame covariance: e^T P^-1 e, e = Log(R_est^T R_true). Chi-square, 3 dof.
double attitudeNees(const Quat& q_ib_est, const Mat3& cov_body, const Quat& q_ib_true);

/// Cross-boresight and roll 1-sigma [rad] of a body-frame covariance (z is the boresight):
/// cross = sqrt(Pxx + Pyy) is the RMS boresight pointing error, roll = sqrt(Pzz).
struct AttitudeSigma {
  double cross_boresight = 0;
  double roll = 0;
};
AttitudeSigma attitudeSigma(const Mat3& cov_body);

}  // namespace st
