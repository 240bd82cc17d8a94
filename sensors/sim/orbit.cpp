#include "sensors/sim/orbit.hpp"

#include <cmath>

#include "common/conventions.hpp"

namespace st {

std::string CircularOrbit::validate() const {
  if (!(altitude_km > 0 && altitude_km < 1e6)) return "'altitude_km' must be in (0, 1e6) km";
  if (!(inclination_deg >= 0 && inclination_deg <= 180))
    return "'inclination_deg' must be in [0, 180]";
  if (!std::isfinite(raan_deg)) return "'raan_deg' must be finite";
  if (!std::isfinite(arg_latitude_deg)) return "'arg_latitude_deg' must be finite";
  if (!(velocity_rate_hz >= 0 && velocity_rate_hz <= 1000))
    return "'velocity_rate_hz' must be in [0, 1000]";
  return "";
}

double CircularOrbit::speedKmS() const { return std::sqrt(kEarthMuKm3S2 / radiusKm()); }

double CircularOrbit::periodS() const { return 2 * kPi * radiusKm() / speedKmS(); }

namespace {
// Perifocal-to-inertial for a circular orbit: position r (cos u, sin u, 0) in the node frame,
// rotated by the inclination about the node line and by the RAAN about the pole.
Vec3 inertial(double raan, double incl, double a, double b) {
  const double cO = std::cos(raan), sO = std::sin(raan), ci = std::cos(incl), si = std::sin(incl);
  return {a * cO - b * ci * sO, a * sO + b * ci * cO, b * si};
}
}  // namespace

Vec3 CircularOrbit::positionAt(double t) const {
  const double u = deg2rad(arg_latitude_deg) + t * speedKmS() / radiusKm();
  return radiusKm() * inertial(deg2rad(raan_deg), deg2rad(inclination_deg), std::cos(u), std::sin(u));
}

Vec3 CircularOrbit::velocityAt(double t) const {
  const double u = deg2rad(arg_latitude_deg) + t * speedKmS() / radiusKm();
  return speedKmS() *
         inertial(deg2rad(raan_deg), deg2rad(inclination_deg), -std::sin(u), std::cos(u));
}

const SectionSchema<CircularOrbit>& orbitSchema() {
  using O = CircularOrbit;
  static const auto s =
      SectionSchema<O>()
          .add("altitude_km", &O::altitude_km, "[km] circular orbit above the equatorial radius")
          .add("inclination_deg", &O::inclination_deg, "[deg] inclination, [0, 180]")
          .add("raan_deg", &O::raan_deg, "[deg] right ascension of the ascending node")
          .add("arg_latitude_deg", &O::arg_latitude_deg,
               "[deg] argument of latitude at t = 0 (0 = the ascending node)")
          .add("velocity_rate_hz", &O::velocity_rate_hz,
               "[Hz] VELOCITY observations per second (0 = none: the sky is aberrated, the "
               "tracker is not told)");
  return s;
}

}  // namespace st
