/// @file epoch_correction.hpp
/// Catalog corrections (seed 003 "Correction for proper motion", "Aberration", "Parallax"):
/// a catalog direction at its own epoch -> the apparent direction seen from the Earth at the
/// observation epoch, in ICRS axes.
///
/// Earth model: a low-precision solar theory (Astronomical Almanac "low precision formulas
/// for the Sun": mean longitude, mean anomaly, two-term equation of centre, radius vector),
/// differentiated analytically for the velocity, referred to J2000 axes by removing general
/// precession in longitude, and rotated by the J2000 obliquity. It is the Earth's heliocentric
/// motion; the Sun's own barycentric motion (<= 0.013 km/s, mostly Jupiter) and the Earth's
/// motion about the Earth-Moon barycentre (0.012 km/s) are neglected. Accuracy over
/// 1950-2050: velocity within ~0.03 km/s of the barycentric velocity (checked against the
/// SOFA/JPL reference in tests/catalog), i.e. the annual aberration (up to 20.5 arcsec) is
/// right to ~0.02 arcsec; position within ~1e-4 AU + 0.01 AU (Sun's barycentric offset), so
/// parallax (<= 0.77 arcsec for Proxima) is right to ~0.01 arcsec.
#pragma once
#include "catalog/star_catalog.hpp"
#include "common/attitude.hpp"
#include "common/aberration.hpp"  // applyAberration (annual here)

namespace st {

/// Earth's position [AU] and velocity [km/s] w.r.t. the solar-system barycentre (approximated
/// by the Sun, see the file comment), ICRS axes, at a Julian-year epoch (TT).
struct EarthState {
  Vec3 position_au;
  Vec3 velocity_km_s;
};
EarthState earthBarycentricState(double epoch_jyear);

/// Barycentric direction of a catalog entry at `epoch_jyear`: rigorous rectilinear space
/// motion with zero radial velocity (Hipparcos gives none): u(t) = normalise(u0 + dt * mu),
/// mu = pm_ra_cosdec * e_ra + pm_dec * e_dec. Exact for straight-line motion at constant
/// speed; neglects only light-time and the perspective acceleration from radial velocity.
Vec3 propagateSpaceMotion(const CatalogEntry& e, double catalog_epoch_jyear, double epoch_jyear);

/// Shift to the observer at `observer_au` (barycentric, AU) for a star of parallax [rad]:
/// normalise(u - parallax * observer_au). No-op for parallax <= 0.
Vec3 applyParallax(const Vec3& u_bary, double parallax, const Vec3& observer_au);


/// All three in order: proper motion to `epoch_jyear`, then parallax and aberration for the
/// Earth at that epoch (each optional).
Vec3 apparentDirection(const CatalogEntry& e, double catalog_epoch_jyear, double epoch_jyear,
                       bool parallax, bool aberration);

}  // namespace st
