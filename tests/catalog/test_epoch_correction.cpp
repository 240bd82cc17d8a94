// Epoch corrections: proper motion (alpha Cen A), Earth velocity against the SOFA/JPL
// reference, aberration and parallax against their first-order formulas.
#include <gtest/gtest.h>

#include <cmath>

#include "catalog/epoch_correction.hpp"
#include "common/conventions.hpp"
#include "tests/catalog/catalog_fixture.hpp"

namespace st {
namespace {

const CatalogEntry& alphaCenA() {
  for (const CatalogEntry& e : test::hipSubset().entries)
    if (e.id == 71683) return e;
  throw std::runtime_error("HIP 71683 not in the subset");
}

// Offsets [arcsec] of `u` from (ra0, dec0) along RA*cos(dec0) and Dec.
Vec2 offsetArcsec(const Vec3& u, double ra0, double dec0) {
  double ra, dec;
  raDecFromVector(u, ra, dec);
  double dra = ra - ra0;
  if (dra > kPi) dra -= kTwoPi;
  if (dra < -kPi) dra += kTwoPi;
  return Vec2(rad2arcsec(dra * std::cos(dec0)), rad2arcsec(dec - dec0));
}

TEST(EpochCorrection, AlphaCenProperMotionMatchesCatalogRates) {
  const CatalogEntry& e = alphaCenA();
  const Vec2 rate(e.pm_ra_cosdec * kArcsecPerRad, e.pm_dec * kArcsecPerRad);  // [arcsec/yr]
  // One year each way from the catalog epoch: the displacement must be the catalog's rates.
  // Second-order terms (the great-circle path in RA/Dec) are ~1e-4 arcsec over one year.
  for (double dt : {1.0, -1.0}) {
    const Vec3 u = propagateSpaceMotion(e, 1991.25, 1991.25 + dt);
    const Vec2 d = offsetArcsec(u, e.ra, e.dec);
    EXPECT_NEAR(d.x(), dt * rate.x(), 0.01) << "dt " << dt;
    EXPECT_NEAR(d.y(), dt * rate.y(), 0.01) << "dt " << dt;
  }
  // Teeth: treating pmRA as if it were not yet times cos(dec) misses by about 3.8 arcsec.
  CatalogEntry wrong = e;
  wrong.pm_ra_cosdec = e.pm_ra_cosdec / std::cos(e.dec);
  const Vec2 dw = offsetArcsec(propagateSpaceMotion(wrong, 1991.25, 1992.25), e.ra, e.dec);
  EXPECT_GT(std::fabs(dw.x() - rate.x()), 1.0);
}

TEST(EpochCorrection, EarthVelocityMatchesSofaEpv00Reference) {
  // SOFA t_sofa_c.c, t_epv00: iauEpv00(2400000.5, 53411.52501161) barycentric position [AU]
  // and velocity [AU/day] of the Earth (a fit to JPL DE405).
  const double jyear = 2000.0 + (2400000.5 + 53411.52501161 - kJdJ2000) / kDaysPerJulianYear;
  const Vec3 pb(-0.7714104440491111971, 0.5598412061824171323, 0.2425996277722452400);
  const Vec3 vb(-0.1091874268116823295e-1, -0.1246525461732861538e-1,
                -0.5404773180966231279e-2);
  const double au_per_day_km_s = kAuKm / kSecondsPerDay;
  const EarthState s = earthBarycentricState(jyear);
  const double dv = (s.velocity_km_s - vb * au_per_day_km_s).norm();
  const double dp = (s.position_au - pb).norm();
  std::printf("[ info ] Earth model vs SOFA epv00: |dv| = %.4f km/s (aberration %.4f arcsec), "
              "|dp| = %.5f AU\n", dv, rad2arcsec(dv / kSpeedOfLightKmS), dp);
  // Budget (epoch_correction.hpp): Sun about the barycentre <= 0.015 km/s, Earth about the
  // Earth-Moon barycentre 0.0125 km/s, theory truncation ~0.005 km/s.
  EXPECT_LT(dv, 0.035);
  // Sun's barycentric offset <= 0.01 AU (Jupiter + Saturn) dominates the position error.
  EXPECT_LT(dp, 0.012);
}

TEST(EpochCorrection, EarthVelocityIsTheDerivativeOfThePosition) {
  for (double y : {1991.25, 2000.0, 2019.573, 2031.9}) {
    const double h = 0.1 / kDaysPerJulianYear;  // 0.1 day
    const Vec3 dp = earthBarycentricState(y + h).position_au - earthBarycentricState(y - h).position_au;
    const Vec3 v_num = dp / (0.2 * kSecondsPerDay) * kAuKm;
    const Vec3 v = earthBarycentricState(y).velocity_km_s;
    EXPECT_LT((v_num - v).norm(), 1e-4) << y;
    EXPECT_GT(v.norm(), 29.2);  // aphelion 29.29 km/s, perihelion 30.29 km/s
    EXPECT_LT(v.norm(), 30.4);
  }
}

TEST(EpochCorrection, AberrationMatchesFirstOrderFormula) {
  const Vec3 v(0, 29.8, 0);  // km/s
  const double beta = 29.8 / kSpeedOfLightKmS;
  for (double theta_deg : {0.0, 30.0, 90.0, 150.0}) {
    const double th = deg2rad(theta_deg);
    const Vec3 u(std::sin(th), std::cos(th), 0);  // angle th from the velocity
    const Vec3 u2 = applyAberration(u, v);
    const double shift = std::atan2(u.cross(u2).norm(), u.dot(u2));
    // first order: beta sin(theta); second order beta^2 sin(2 theta)/4 = 1e-8 rad = 0.002"
    EXPECT_NEAR(rad2arcsec(shift), rad2arcsec(beta * std::sin(th)), 0.003) << theta_deg;
    EXPECT_GE(u2.y(), u.y() - 1e-15);  // towards the apex
  }
}

TEST(EpochCorrection, ParallaxShiftsByParallaxTimesSinAngle) {
  const CatalogEntry& e = alphaCenA();
  const Vec3 u = propagateSpaceMotion(e, 1991.25, 1991.25);
  const Vec3 perp = u.unitOrthogonal();  // observer 1 AU away, perpendicular to the star
  const Vec3 u2 = applyParallax(u, e.parallax, perp);
  const double shift = std::atan2(u.cross(u2).norm(), u.dot(u2));
  EXPECT_NEAR(rad2arcsec(shift), 742.12e-3, 1e-6);
  EXPECT_EQ(applyParallax(u, 0.0, perp), u);
  // apparentDirection with both corrections off is the space motion alone
  const Vec3 a = apparentDirection(e, 1991.25, 2020.0, false, false);
  EXPECT_EQ(a, propagateSpaceMotion(e, 1991.25, 2020.0));
  // and with them on it moves by no more than aberration + parallax (20.5" + 0.75")
  const Vec3 b = apparentDirection(e, 1991.25, 2020.0, true, true);
  EXPECT_LT(rad2arcsec(std::atan2(a.cross(b).norm(), a.dot(b))), 21.3);
}

}  // namespace
}  // namespace st
