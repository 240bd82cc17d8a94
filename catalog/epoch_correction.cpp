// Catalog corrections to the observation epoch; the Earth model and its accuracy are
// described in epoch_correction.hpp.
#include "catalog/epoch_correction.hpp"

#include <cmath>

#include "common/conventions.hpp"

namespace st {
namespace {

constexpr double kObliquityJ2000 = deg2rad(23.4392911);   // IAU 1980 mean obliquity at J2000
constexpr double kPrecessionDegPerCentury = 1.396971;     // general precession in longitude
constexpr double kAberrationConstantDeg = 20.49552 / 3600.0;  // the Almanac's L is apparent

}  // namespace

EarthState earthBarycentricState(double epoch_jyear) {
  // Astronomical Almanac low-precision Sun (sec. C): n days from J2000.0.
  const double n = (epoch_jyear - 2000.0) * kDaysPerJulianYear;
  const double T = n / 36525.0;
  const double g = deg2rad(357.528 + 0.9856003 * n);  // mean anomaly
  const double dg = deg2rad(0.9856003);               // [rad/day]
  // Geometric longitude of the Sun, J2000 equinox: add back the aberration the Almanac's
  // mean longitude contains, subtract the precession accumulated since J2000.
  const double lambda =
      deg2rad(280.460 + 0.9856474 * n + kAberrationConstantDeg - kPrecessionDegPerCentury * T +
              1.915 * std::sin(g) + 0.020 * std::sin(2 * g));
  const double dlambda = deg2rad(0.9856474 - kPrecessionDegPerCentury / 36525.0) +
                         deg2rad(1.915 * std::cos(g) + 0.040 * std::cos(2 * g)) * dg;
  const double r = 1.00014 - 0.01671 * std::cos(g) - 0.00014 * std::cos(2 * g);  // [AU]
  const double dr = (0.01671 * std::sin(g) + 0.00028 * std::sin(2 * g)) * dg;    // [AU/day]
  // Earth = -(geocentric Sun), in ecliptic J2000 coordinates.
  const double cl = std::cos(lambda), sl = std::sin(lambda);
  const Vec3 p_ecl(-r * cl, -r * sl, 0.0);
  const Vec3 v_ecl(-(dr * cl - r * sl * dlambda), -(dr * sl + r * cl * dlambda), 0.0);
  const double ce = std::cos(kObliquityJ2000), se = std::sin(kObliquityJ2000);
  auto toEquatorial = [&](const Vec3& e) {
    return Vec3(e.x(), ce * e.y() - se * e.z(), se * e.y() + ce * e.z());
  };
  EarthState s;
  s.position_au = toEquatorial(p_ecl);
  s.velocity_km_s = toEquatorial(v_ecl) * (kAuKm / kSecondsPerDay);
  return s;
}

Vec3 propagateSpaceMotion(const CatalogEntry& e, double catalog_epoch_jyear, double epoch_jyear) {
  const double cr = std::cos(e.ra), sr = std::sin(e.ra), cd = std::cos(e.dec),
               sd = std::sin(e.dec);
  const Vec3 u0(cd * cr, cd * sr, sd);
  const Vec3 e_ra(-sr, cr, 0.0);
  const Vec3 e_dec(-sd * cr, -sd * sr, cd);
  const double dt = epoch_jyear - catalog_epoch_jyear;
  // Straight-line motion in space (zero radial velocity): the tangential velocity over
  // distance is the proper-motion vector, so the direction is u0 + dt * mu, normalised.
  return (u0 + dt * (e.pm_ra_cosdec * e_ra + e.pm_dec * e_dec)).normalized();
}

Vec3 applyParallax(const Vec3& u_bary, double parallax, const Vec3& observer_au) {
  if (!(parallax > 0)) return u_bary;
  // Star at distance 1/parallax AU along u: seen from the observer it is at u/p - o.
  return (u_bary - parallax * observer_au).normalized();
}

Vec3 apparentDirection(const CatalogEntry& e, double catalog_epoch_jyear, double epoch_jyear,
                       bool parallax, bool aberration) {
  Vec3 u = propagateSpaceMotion(e, catalog_epoch_jyear, epoch_jyear);
  if (!parallax && !aberration) return u;
  const EarthState earth = earthBarycentricState(epoch_jyear);
  if (parallax) u = applyParallax(u, e.parallax, earth.position_au);
  if (aberration) u = applyAberration(u, earth.velocity_km_s);
  return u;
}

}  // namespace st
