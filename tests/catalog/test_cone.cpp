// Cone / FOV query (seed 002 spherical-polygon search) against brute force.
#include <gtest/gtest.h>

#include <random>

#include "catalog/star_database.hpp"
#include "common/conventions.hpp"
#include "tests/catalog/catalog_fixture.hpp"

namespace st {
namespace {

Vec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0, 1);
  Vec3 v(n(rng), n(rng), n(rng));
  return v.normalized();
}

TEST(StarDatabaseCone, EqualsBruteForceOn1000RandomAttitudes) {
  const StarDatabase& db = test::hipDatabase15();
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> rad(0.0, deg2rad(20.0));
  std::vector<uint32_t> got, want;
  std::size_t total = 0;
  for (int q = 0; q < 1000; ++q) {
    const Vec3 axis = randomUnit(rng);
    const double r = q < 10 ? 0.0 : rad(rng);
    db.coneQuery(axis, r, got);
    want.clear();
    const double cr = std::cos(r);
    for (uint32_t i = 0; i < db.stars().size(); ++i)
      if (db.stars()[i].u_i.dot(axis) >= cr) want.push_back(i);
    ASSERT_EQ(got, want) << "query " << q << " radius " << rad2deg(r) << " deg";
    total += got.size();
  }
  EXPECT_GT(total, 10000u);  // the queries are not trivially empty
}

TEST(StarDatabaseCone, QueryAtEveryStarFindsItAndPoles) {
  const StarDatabase& db = test::hipDatabase15();
  std::vector<uint32_t> got;
  for (uint32_t i = 0; i < db.stars().size(); i += 37) {
    db.coneQuery(db.stars()[i].u_i, arcsec2rad(1), got);
    ASSERT_FALSE(got.empty());
    EXPECT_NE(std::find(got.begin(), got.end(), i), got.end());
  }
  for (const Vec3& pole : {Vec3(0, 0, 1), Vec3(0, 0, -1), Vec3(1, 0, 0), Vec3(0, -1, 0)}) {
    db.coneQuery(pole, deg2rad(10), got);
    std::size_t want = 0;
    for (const Star& s : db.stars()) want += s.u_i.dot(pole) >= std::cos(deg2rad(10));
    EXPECT_EQ(got.size(), want);
  }
}

TEST(StarDatabaseCone, RectangleEqualsBruteForce) {
  const StarDatabase& db = test::hipDatabase15();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> ang(-kPi, kPi);
  const double tx = std::tan(deg2rad(5.7)), ty = std::tan(deg2rad(4.3));
  std::vector<uint32_t> got, want;
  for (int q = 0; q < 300; ++q) {
    const Quat q_ib = quatExp(Vec3(ang(rng), ang(rng), ang(rng)) / 2);
    db.rectangleQuery(q_ib, tx, ty, got);
    const Mat3 R = q_ib.normalized().toRotationMatrix();
    want.clear();
    for (uint32_t i = 0; i < db.stars().size(); ++i) {
      const Vec3 v = R.transpose() * db.stars()[i].u_i;
      if (v.z() > 0 && std::fabs(v.x()) <= tx * v.z() && std::fabs(v.y()) <= ty * v.z())
        want.push_back(i);
    }
    ASSERT_EQ(got, want) << "attitude " << q;
  }
}

}  // namespace
}  // namespace st
