// The display geometry of seed 001 sec. IV (eqs. 53-58): round trips, the far-field limit and
// the size of the near-field error at the seed's geometry.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/conventions.hpp"
#include "sensors/testbed/display_geometry.hpp"
#include "sensors/testbed/master_angle_match.hpp"
#include "sensors/testbed/tass_bench.hpp"

namespace st::testbed {
namespace {

double angle(const Vec3& a, const Vec3& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

Quat smallAttitude(std::mt19937_64& rng, double max_deg) {
  std::uniform_real_distribution<double> u(-max_deg, max_deg);
  return quatFromYpr(Vec3(deg2rad(u(rng)), deg2rad(u(rng)), deg2rad(u(rng))));
}

// Screen point -> camera vector -> screen point, and -> database vector, to 1e-12 at
// attitudes up to 10 deg; the near-field vector at the true attitude is A r (eq. 54).
TEST(DisplayGeometry, RoundTripsAreExact) {
  const DisplayGeometry g;
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> ux(0, g.screen_width_px - 1), uy(0, g.screen_height_px - 1);
  for (int t = 0; t < 200; ++t) {
    const Quat q = smallAttitude(rng, 10);
    const Vec2 px(ux(rng), uy(rng));
    const Vec3 S = g.screenPoint(px);
    EXPECT_LE((g.screenPixel(S) - px).norm(), 1e-9);
    const Vec3 b = g.cameraVector(S, q);
    EXPECT_NEAR(b.norm(), 1.0, 1e-15);
    const auto back = g.screenPointFromCamera(b, q);
    ASSERT_TRUE(back);
    EXPECT_LE((*back - S).norm(), 1e-12);
    const Vec3 r = DisplayGeometry::databaseVector(S);
    EXPECT_NEAR(g.beta(r), S.norm(), 1e-12);  // eq. 57
    const auto w = g.nearFieldVector(b, q);
    ASSERT_TRUE(w);
    EXPECT_LE((*w - q.conjugate() * r).norm(), 1e-12);  // eq. 54 / beta: w = A r
    // eq. 58: the database built from a camera image at zero attitude.
    const auto r0 = g.databaseFromZeroAttitude(g.cameraVector(S, Quat::Identity()));
    ASSERT_TRUE(r0);
    EXPECT_LE((*r0 - r).norm(), 1e-12);
  }
}

TEST(DisplayGeometry, EulerAnglesRoundTrip) {
  const Vec3 ypr(0.3, -0.2, 0.1);
  EXPECT_LE((yprFromQuat(quatFromYpr(ypr)) - ypr).norm(), 1e-14);
  // yaw about z, then pitch about y, then roll about x (R = Rz Ry Rx)
  const Quat q = quatFromYpr(Vec3(0, 0, kPi / 2));
  EXPECT_LE((q * Vec3::UnitY() - Vec3::UnitZ()).norm(), 1e-15);
}

// Far field: with the screen a million times further (stars at the same directions from the
// centre of rotation) the camera's angles are the database's to the lever arm / h ratio.
TEST(DisplayGeometry, FarFieldLimitGivesTheOrdinaryAngles) {
  const TassBench bench;
  const std::vector<Vec2> px = bench.starPixels();
  for (double scale : {1.0, 1e6}) {
    DisplayGeometry g = bench.display;
    g.screen_distance_m *= scale;
    g.screen_width_m *= scale;
    g.screen_height_m *= scale;
    double worst = 0;
    for (std::size_t i = 0; i < px.size(); ++i)
      for (std::size_t j = i + 1; j < px.size(); ++j) {
        const Vec3 Si = g.screenPoint(px[i]), Sj = g.screenPoint(px[j]);
        const double cam = angle(g.cameraVector(Si, Quat::Identity()),
                                 g.cameraVector(Sj, Quat::Identity()));
        const double db = angle(DisplayGeometry::databaseVector(Si),
                                DisplayGeometry::databaseVector(Sj));
        worst = std::max(worst, std::abs(cam - db));
      }
    std::cout << "[ FARFIELD ] h = " << g.screen_distance_m << " m: largest camera-database "
              << "angle difference " << rad2arcsec(worst) << " arcsec\n";
    if (scale == 1.0) {
      EXPECT_GT(worst, arcsec2rad(3600));  // the near-field error is degrees at the bench
    } else {
      EXPECT_LT(worst, 1e-6 * 10);  // ~ |R_0| / h = 2.6e-7 times the pattern's size
    }
  }
}

TEST(DisplayGeometry, InvalidGeometryIsNamed) {
  DisplayGeometry g;
  std::string why;
  EXPECT_TRUE(g.isValid(&why)) << why;
  g.lever_arm_m = Vec3(0, 0, 2.0);
  EXPECT_FALSE(g.isValid(&why));
  EXPECT_NE(why.find("lever arm"), std::string::npos);
  g = DisplayGeometry();
  g.screen_distance_m = -1;
  EXPECT_FALSE(g.isValid(&why));
  EXPECT_NE(why.find("screen distance"), std::string::npos);
}

TEST(MasterAngleMatch, IdentifiesAPatternAndDropsAmbiguousAngles) {
  const TassBench bench;
  const auto db = AngleDatabase([&] {
    std::vector<Vec3> r;
    for (const Vec2& p : bench.starPixels())
      r.push_back(DisplayGeometry::databaseVector(bench.display.screenPoint(p)));
    return r;
  }());
  // Observed = the database itself, rotated, star 0 first, order shuffled: all 9 identified
  // with a tiny window.
  const Quat q = quatFromYpr(Vec3(0.1, 0.05, -0.02));
  std::vector<int> order = {0, 5, 3, 8, 1, 7, 2, 6, 4};
  std::vector<Vec3> obs;
  for (int k : order) obs.push_back(q.conjugate() * db.stars()[k]);
  const MasterAngleMatch m = matchMasterAngles(obs, db, arcsec2rad(1));
  ASSERT_EQ(m.master_star, 0) << m.reason;
  ASSERT_EQ(m.stars.size(), 9u);
  for (const auto& [k, star] : m.stars) EXPECT_EQ(star, order[k]);
  // A window as wide as the pattern fits every angle to many pairs: nothing unique.
  const MasterAngleMatch wide = matchMasterAngles(obs, db, deg2rad(20));
  EXPECT_EQ(wide.master_star, -1);
  EXPECT_EQ(wide.angles_ambiguous, 8);
}

}  // namespace
}  // namespace st::testbed
