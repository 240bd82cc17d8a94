/// @file conventions.hpp
/// The project's conventions, written once: units, frames, the quaternion convention and
/// the attitude-error metrics. Every other file uses these names instead of restating them.
///
/// Units
///   Radians and seconds inside the code. Degrees and arcseconds only at the edges (CLI,
///   reports); variables that are not in radians carry the unit in their name
///   (`fov_deg`, `sigma_arcsec`). Convert with the constants below, nowhere else.
///
/// Frames
///   Inertial (i): ICRS, J2000 axes. Catalog positions are propagated to the observation
///     epoch (proper motion, parallax) and optionally corrected for annual aberration.
///   Camera (c): +z along the boresight, +x towards increasing column, +y towards
///     increasing row (OpenCV). Pixel centres are at integer coordinates: the pixel (0,0)
///     covers [-0.5, 0.5] x [-0.5, 0.5].
///   Body (b): the camera frame unless a sensor pose (mrpt::poses::CPose3D) is set.
///
/// Attitude
///   Unit quaternion, Hamilton, scalar first (w, x, y, z), like mrpt::math::CQuaternionDouble.
///   `q_ib` is the orientation of the body in the inertial frame:
///       v_i = R(q_ib) * v_b          (subscripts cancel: v_i = R_ib * v_b)
///   Name every rotation this way (`R_cam_body`, `q_ib`). The seed papers' attitude matrix is
///   A = R_ib^T (maps inertial to body). Quaternions are kept canonical (w >= 0).
///   Trap: Eigen stores coeffs() as (x, y, z, w); never Map an MRPT quaternion onto Eigen's.
///   Use the conversions in common/mrpt_convert.hpp.
///
/// Covariance of an attitude: 3x3, of the small rotation error `dtheta` expressed in the
///   BODY frame, in rad^2:  R_true = R_est * Exp(dtheta).
///
/// Attitude error of an estimate against truth (AttitudeError in attitude.hpp):
///   R_err = R_est^T * R_true (body frame). Total = angle of R_err. It is split by the
///   swing-twist decomposition about +z: cross-boresight = angle between the two boresights
///   (swing), roll = signed twist about the boresight.
///
/// RA / Dec / roll (RaDecRoll in attitude.hpp)
///   The boresight points at (ra, dec). At roll = 0 the camera +y axis (image "down") points
///   to celestial south and +x to the west, i.e. the image shows north up and east left, as
///   the sky is seen from inside the sphere. Roll rotates the camera about its +z axis:
///       R_ib = [-east | -north | boresight] * Rz(roll).
///
/// Time
///   mrpt::Clock::time_point in observations; seconds as double in CSV; epochs of star
///   positions as Julian years (TT ~ UTC at the accuracy needed here), e.g. 2019.573.
#pragma once
#include <cmath>

namespace st {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2.0 * kPi;
constexpr double kDegPerRad = 180.0 / kPi;
constexpr double kRadPerDeg = kPi / 180.0;
constexpr double kArcsecPerRad = 3600.0 * kDegPerRad;
constexpr double kRadPerArcsec = 1.0 / kArcsecPerRad;
constexpr double kRadPerMas = kRadPerArcsec / 1000.0;

constexpr double deg2rad(double deg) { return deg * kRadPerDeg; }
constexpr double rad2deg(double rad) { return rad * kDegPerRad; }
constexpr double rad2arcsec(double rad) { return rad * kArcsecPerRad; }
constexpr double arcsec2rad(double arcsec) { return arcsec * kRadPerArcsec; }

/// Julian date of J2000.0 (2000-01-01 12:00 TT) and the length of a Julian year.
constexpr double kJdJ2000 = 2451545.0;
constexpr double kDaysPerJulianYear = 365.25;
constexpr double kSecondsPerDay = 86400.0;
/// Julian date of the Unix epoch (1970-01-01 00:00 UTC).
constexpr double kJdUnixEpoch = 2440587.5;

/// Julian year (e.g. 2019.57) of a Unix time in seconds.
constexpr double julianYearFromUnixSeconds(double unix_s) {
  return 2000.0 + ((unix_s / kSecondsPerDay + kJdUnixEpoch) - kJdJ2000) / kDaysPerJulianYear;
}
constexpr double unixSecondsFromJulianYear(double jyear) {
  return ((jyear - 2000.0) * kDaysPerJulianYear + kJdJ2000 - kJdUnixEpoch) * kSecondsPerDay;
}

/// Speed of light [km/s] and the astronomical unit [km], for aberration.
constexpr double kSpeedOfLightKmS = 299792.458;
constexpr double kAuKm = 149597870.7;

/// Flux of a star of V magnitude `vmag` relative to one of V 0 (Pogson: 5 mag = 100x).
inline double relativeFlux(double vmag) { return std::pow(10.0, -0.4 * vmag); }

}  // namespace st
