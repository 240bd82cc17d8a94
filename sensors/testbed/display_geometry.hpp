/// @file display_geometry.hpp
/// The near-field star display testbed of seed 001 sec. IV (TASS): a flat screen at a finite
/// distance above a platform that rotates about a fixed point, a camera on the platform offset
/// from that point by a lever arm. In space a translation of the camera is unobservable; here
/// it changes the angles between stars, so the vectors must be corrected (eqs. 53-58).
///
/// Frames (seed 001 Fig. 3, written in this project's conventions):
///   I  (testbed "inertial"): origin at the centre of rotation, +z up towards the screen (the
///      seed's camera looks along -z with p = [0 0 -1]; we keep the project's +z boresight,
///      so p = +z here), +x along the screen's columns, +y along its rows. The screen plane is
///      z = h and its centre is on the z axis.
///   B  (body = camera, conventions.hpp): +z boresight; at zero attitude B is parallel to I.
///      q_ib is the platform's attitude, v_I = R(q_ib) v_B; the seed's A = R(q_ib)^T.
///   The camera's optical centre sits at R_0 (the lever arm, body axes) from the origin of I.
///
/// A point S on the screen is seen by the camera along b^B = R_ib^T (S - R_ib R_0) / alpha
/// (eq. 53/54, alpha the camera-to-star distance), and from the centre of rotation along the
/// database vector r = S / beta (eq. 57/58). MRPT-free.
#pragma once
#include <optional>
#include <string>

#include "common/attitude.hpp"

namespace st::testbed {

/// Everything the seed leaves unstated about its bench, in one place (defaults and why).
struct DisplayGeometry {
  /// [m] h: centre of rotation to the screen plane (seed 001 sec. IV.A, eq. 55).
  double screen_distance_m = 1.7695;
  /// [m] R_0^{B'}: camera optical centre from the centre of rotation, body axes. Not in the
  /// seed: TASS is 1.5 m across (5 ft) with the camera "sticking out the top" (Fig. 1), so
  /// the camera sits 0.55 m above the centre of rotation and 0.5 m off the vertical axis,
  /// towards the rim. (A camera on the axis would see a near-field error almost independent
  /// of the attitude prediction: the correction moves each vector along itself, and only
  /// the parallax |R_0 x b| / alpha turns that into an angle.)
  Vec3 lever_arm_m = Vec3(0.40, 0.30, 0.55);
  /// [m] (x, y) of the screen's centre in frame I: hung above the camera (the lever arm's
  /// x, y) so that the camera at zero attitude looks at the middle of the screen.
  Vec2 screen_centre_m = Vec2(0.40, 0.30);
  /// The screen: a 24" 16:10 LCD monitor of 2011 (1920 x 1200 px, 0.27 mm pitch); the seed
  /// only says "LCD monitor".
  int screen_width_px = 1920, screen_height_px = 1200;
  double screen_width_m = 0.5184, screen_height_m = 0.324;

  /// The stages' one validation signature: false and *why (what is wrong) when invalid,
  /// e.g. |R_0| >= h (the camera must stay below the screen).
  bool isValid(std::string* why = nullptr) const;

  double pitchX() const { return screen_width_m / screen_width_px; }   ///< [m/px]
  double pitchY() const { return screen_height_m / screen_height_px; }  ///< [m/px]

  /// Screen pixel (column, row; centres at integer coordinates) -> point in frame I [m].
  Vec3 screenPoint(const Vec2& screen_px) const;
  /// Inverse of screenPoint for a point on the plane z = h.
  Vec2 screenPixel(const Vec3& point_I) const;
  bool isOnScreen(const Vec2& screen_px) const;

  /// Camera centre in frame I: R_ib R_0.
  Vec3 cameraCentre(const Quat& q_ib) const;
  /// Unit vector b^B from the camera to screen point S at attitude q_ib (eq. 53/54).
  Vec3 cameraVector(const Vec3& point_I, const Quat& q_ib) const;
  /// alpha_i: distance from the camera along b^B to the screen plane when the attitude is
  /// q_ib (eq. 56); nullopt when the ray does not go up to the screen.
  std::optional<double> alpha(const Vec3& b_B, const Quat& q_ib) const;
  /// The screen point on the ray b^B at attitude q_ib: R_ib (R_0 + alpha b).
  std::optional<Vec3> screenPointFromCamera(const Vec3& b_B, const Quat& q_ib) const;
  /// The near-field vector: the direction of R_0 + alpha_i b_i (eq. 54 divided by beta_i),
  /// with alpha from the PREDICTED attitude. Equals A r_i when the prediction is right, so
  /// its angles are the database's angles (sec. IV.B).
  std::optional<Vec3> nearFieldVector(const Vec3& b_B, const Quat& q_ib_pred) const;
  /// beta_i = h / (p . r) (eq. 57): distance from the centre of rotation to the star.
  double beta(const Vec3& r_I) const;
  /// Database vector of a screen point: r = S / beta (eq. 57/58), a unit vector in frame I.
  static Vec3 databaseVector(const Vec3& point_I) { return point_I.normalized(); }
  /// Database vector from a camera measurement taken at zero attitude (eq. 58 with A = I):
  /// (R_0 + alpha b) / beta. How the seed built its database from a camera image.
  std::optional<Vec3> databaseFromZeroAttitude(const Vec3& b_B) const;
};

/// Attitude from yaw, pitch, roll [rad] about z, y, x: R = Rz(yaw) Ry(pitch) Rx(roll) (MRPT
/// CPose3D's order; the seed's psi, theta, phi of a 3-2-1 sequence).
Quat quatFromYpr(const Vec3& ypr);
/// Inverse of quatFromYpr (pitch in [-pi/2, pi/2]).
Vec3 yprFromQuat(const Quat& q);

}  // namespace st::testbed
