// Selection: double-star merge (seed 004 eqs. 6.1/6.2), magnitude limit, uniform density,
// the build report, and the neighbour table (seed 002).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "catalog/star_database.hpp"
#include "catalog/star_selection.hpp"
#include "common/conventions.hpp"
#include "tests/catalog/catalog_fixture.hpp"

namespace st {
namespace {

TEST(DoubleStars, CombinedMagnitudeEq61) {
  EXPECT_NEAR(combinedMagnitude(3.0, 3.0), 3.0 - 2.5 * std::log10(2.0), 1e-12);
  EXPECT_NEAR(combinedMagnitude(1.0, 6.0), 1.0 - 2.5 * std::log10(1.01), 1e-12);
  EXPECT_NEAR(combinedMagnitude(6.0, 1.0), combinedMagnitude(1.0, 6.0), 1e-12);
}

TEST(DoubleStars, MergeUsesIntensityWeightedDirectionEq62) {
  const Vec3 a = unitVectorFromRaDec(1.0, 0.3);
  const double sep = arcsec2rad(5.0);
  const Vec3 b = (a + sep * a.unitOrthogonal()).normalized();  // 5" away
  const Vec3 far = unitVectorFromRaDec(2.0, -0.3);
  const std::vector<SelectedStar> in = {{1, a, 2.0}, {2, b, 3.0}, {3, far, 4.0}};
  std::size_t groups = 0, absorbed = 0;
  std::vector<SelectedStar> out = mergeDoubleStars(in, arcsec2rad(10.0), &groups, &absorbed);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(groups, 1u);
  EXPECT_EQ(absorbed, 1u);
  std::sort(out.begin(), out.end(), [](auto& x, auto& y) { return x.id < y.id; });
  EXPECT_EQ(out[0].id, 1u);  // the brighter member names the blend
  EXPECT_NEAR(out[0].mag, combinedMagnitude(2.0, 3.0), 1e-12);
  const double w_b = std::pow(10.0, -0.4 * 3.0) / (std::pow(10.0, -0.8) + std::pow(10.0, -1.2));
  const double off = std::atan2(a.cross(out[0].u).norm(), a.dot(out[0].u));
  EXPECT_NEAR(rad2arcsec(off), 5.0 * w_b, 1e-6);  // 1.42" towards the fainter star
  EXPECT_EQ(out[1].u, far);
  // Below the threshold nothing merges.
  EXPECT_EQ(mergeDoubleStars(in, arcsec2rad(4.0)).size(), 3u);
}

TEST(StarDatabaseBuild, ReportCountsAndInvariants) {
  const StarDatabase& db = test::hipDatabase15();
  const BuildReport& r = db.report();
  std::printf("[ info ] build: %zu entries (%zu no position) -> %zu merge candidates -> %zu "
              "double groups (%zu absorbed) -> %zu after V<=6.5 -> %zu stars, %zu pairs, "
              "k-vector %zu, %zu neighbour entries, %.3f s\n",
              r.catalog_entries, r.skipped_no_position, r.merge_candidates, r.double_star_groups,
              r.stars_merged_away, r.after_mag_limit, r.after_density, r.pairs, r.kvector_size,
              r.neighbour_entries, r.build_seconds);
  EXPECT_EQ(r.catalog_entries, test::hipSubset().entries.size());
  EXPECT_LE(r.after_mag_limit, r.merge_candidates - r.stars_merged_away);
  EXPECT_EQ(r.after_density, db.stars().size());
  // Every merged candidate the database does not keep is a blend-screen star, no brighter than
  // the faintest kept one unless the density reduction dropped it, no fainter than the margin.
  EXPECT_EQ(r.screen_stars, db.screenStars().size());
  EXPECT_EQ(r.screen_stars + db.stars().size(), r.merge_candidates - r.stars_merged_away);
  for (const ScreenStar& s : db.screenStars()) EXPECT_LE(s.mag, db.params().mag_limit + 2.5);
  if (db.params().max_stars_per_region == 0) {
    for (const ScreenStar& s : db.screenStars()) EXPECT_GT(s.mag, db.params().mag_limit);
  }
  std::vector<uint32_t> got;
  const Vec3 axis = db.stars()[7].u_i;
  db.screenConeQuery(axis, deg2rad(3), got);
  std::vector<uint32_t> want;
  for (uint32_t i = 0; i < db.screenStars().size(); ++i)
    if (db.screenStars()[i].u_i.dot(axis) >= std::cos(deg2rad(3))) want.push_back(i);
  EXPECT_EQ(got, want);
  EXPECT_GT(got.size(), 0u);
  EXPECT_EQ(r.pairs, db.pairs().size());
  EXPECT_EQ(r.kvector_size, db.pairKVector().size());
  for (std::size_t i = 0; i < db.stars().size(); ++i) {
    EXPECT_LE(db.stars()[i].mag, 6.5f);
    if (i > 0) {
      ASSERT_LE(db.stars()[i - 1].mag, db.stars()[i].mag);
    }
    ASSERT_NEAR(db.stars()[i].u_i.norm(), 1.0, 1e-12);
  }
  for (const StarPair& p : db.pairs()) {
    ASSERT_LT(p.a, p.b);
    ASSERT_LE(p.theta, float(db.params().max_pair_angle) * (1 + 1e-6f));
  }
  // Every pair closer than the limit is present: count by brute force over all star pairs.
  std::size_t n = 0;
  const double c = std::cos(db.params().max_pair_angle);
  for (std::size_t i = 0; i < db.stars().size(); ++i)
    for (std::size_t j = i + 1; j < db.stars().size(); ++j)
      n += db.stars()[i].u_i.dot(db.stars()[j].u_i) >= c;
  EXPECT_EQ(n, db.pairs().size());
}

TEST(StarDatabaseBuild, UniformDensityKeepsLocalBrightestAndThins) {
  DatabaseParams p = test::params15();
  p.max_stars_per_region = 6;
  p.region_radius = deg2rad(5.0);
  const StarDatabase red = StarDatabase::build(test::hipSubset(), p);
  const StarDatabase& full = test::hipDatabase15();
  std::printf("[ info ] uniform density N=6 per 5 deg cone: %zu -> %zu stars, %zu pairs\n",
              full.stars().size(), red.stars().size(), red.pairs().size());
  EXPECT_LT(red.stars().size(), full.stars().size() * 3 / 4);
  std::set<uint32_t> kept;
  for (const Star& s : red.stars()) kept.insert(s.id);
  std::set<uint32_t> all;
  for (const Star& s : full.stars()) all.insert(s.id);
  for (uint32_t id : kept) ASSERT_TRUE(all.count(id)) << id;
  // A star that is the brightest within 2r of itself is the brightest of the cone around the
  // nearest sweep centre (closer than r), so it must be kept.
  std::vector<uint32_t> near;
  for (uint32_t i = 0; i < full.stars().size(); ++i) {
    full.coneQuery(full.stars()[i].u_i, 2 * p.region_radius, near);
    if (near.front() == i) {
      ASSERT_TRUE(kept.count(full.stars()[i].id)) << "star " << i;
    }
  }
  // The densest cone is thinned: at most ~N stars in any cone of radius r/2 (dense grid check).
  std::size_t max_full = 0, max_red = 0;
  std::mt19937_64 rng(1);
  std::normal_distribution<double> g(0, 1);
  for (int q = 0; q < 2000; ++q) {
    const Vec3 c = Vec3(g(rng), g(rng), g(rng)).normalized();
    full.coneQuery(c, p.region_radius, near);
    max_full = std::max(max_full, near.size());
    red.coneQuery(c, p.region_radius, near);
    max_red = std::max(max_red, near.size());
  }
  EXPECT_LT(max_red, max_full);
}

TEST(StarDatabaseNeighbours, EqualBruteForceNearestFirst) {
  const StarDatabase& db = test::hipDatabase15();
  const double c = std::cos(db.params().neighbour_radius);
  std::size_t total = 0;
  for (uint32_t i = 0; i < db.stars().size(); i += 7) {
    std::vector<uint32_t> want;
    for (uint32_t j = 0; j < db.stars().size(); ++j)
      if (j != i && db.stars()[i].u_i.dot(db.stars()[j].u_i) >= c) want.push_back(j);
    std::vector<uint32_t> got(db.neighboursBegin(i), db.neighboursEnd(i));
    for (std::size_t k = 1; k < got.size(); ++k)
      ASSERT_GE(db.stars()[i].u_i.dot(db.stars()[got[k - 1]].u_i),
                db.stars()[i].u_i.dot(db.stars()[got[k]].u_i));
    std::sort(got.begin(), got.end());
    ASSERT_EQ(got, want) << "star " << i;
    total += got.size();
  }
  EXPECT_GT(total, 1000u);
}

}  // namespace
}  // namespace st
