/// @file orbit.hpp
/// The observer's orbit for the aberration of its own velocity (issue 16 item 3; seed 003
/// "Aberration": Oersted's 600 km polar orbit, "up to 5.7 arc sec"). A circular Keplerian
/// orbit is enough: the aberration depends on the velocity only, and a circular orbit's speed
/// sqrt(mu / a) and its direction, turning once per period, are what a star tracker sees.
///
/// Frame: the inertial frame of the star database (ICRS axes, taken as the Earth's equator and
/// equinox: precession over a mission is far below the effect). Velocity relative to the
/// Earth's centre [km/s] (the rawlog contract's VELOCITY).
///
/// Scenario .ini section (named by [scenario] orbit_section, default "orbit"; absent = an
/// observer at rest relative to the Earth's centre):
///   altitude_km = 600          above the equatorial radius 6378.137 km, > 0
///   inclination_deg = 90       [0, 180]
///   raan_deg = 0               right ascension of the ascending node
///   arg_latitude_deg = 0       argument of latitude at t = 0 (0 = ascending node)
///   velocity_rate_hz = 1       VELOCITY samples per second (0 = none: the sky is aberrated
///                              but the tracker is not told, e.g. to see the error)
#pragma once
#include <string>

#include "common/attitude.hpp"
#include "config/schema.hpp"

namespace st {

inline constexpr double kEarthMuKm3S2 = 398600.4418;        ///< GM of the Earth (WGS 84)
inline constexpr double kEarthEquatorialRadiusKm = 6378.137;

struct CircularOrbit {
  double altitude_km = 600;
  double inclination_deg = 90;
  double raan_deg = 0;
  double arg_latitude_deg = 0;
  double velocity_rate_hz = 1;

  /// "" when usable, else what is wrong (naming the key).
  std::string validate() const;
  double radiusKm() const { return kEarthEquatorialRadiusKm + altitude_km; }
  /// [km/s] circular speed sqrt(mu / r).
  double speedKmS() const;
  /// [s] 2 pi r / v.
  double periodS() const;
  /// [km] position and [km/s] velocity at t [s] from the scenario's start.
  Vec3 positionAt(double t) const;
  Vec3 velocityAt(double t) const;
};

const SectionSchema<CircularOrbit>& orbitSchema();

}  // namespace st
