// The streak a blind (rate-less) lost-in-space frame draws, from its blobs' shapes
// (streakFromShapes): a bright streak that broke into pieces must not set the length.
#include <gtest/gtest.h>

#include <cmath>

#include "sensors/detect/streaks.hpp"

namespace st {
namespace {

constexpr double kPsf = 1.0;

/// A blob of a streak segment of `length` px along `angle`, centred at `px`: second moments
/// L^2/12 + s^2 along and s^2 across.
Centroid segment(const Vec2& px, double length, double angle, double flux) {
  Centroid c;
  c.px = px;
  c.flux = flux;
  c.flags = kElongated;
  const Vec2 u(std::cos(angle), std::sin(angle)), n(-u.y(), u.x());
  c.shape = (length * length / 12 + kPsf * kPsf) * u * u.transpose() + kPsf * kPsf * n * n.transpose();
  return c;
}

DetectorOptions options() {
  DetectorOptions o;
  o.psf_sigma_px = kPsf;
  return o;
}

TEST(StreakShapes, WholeStreaksGiveTheirLengthAndAxis) {
  const double L = 13, a = 0.2;
  std::vector<Centroid> stars;
  for (int k = 0; k < 5; ++k) stars.push_back(segment(Vec2(50 + 60 * k, 40 + 70 * k), L, a, 900 - 100 * k));
  const auto b = streakFromShapes(stars, options());
  ASSERT_TRUE(b);
  EXPECT_NEAR(b->norm(), L, 1e-9);
  EXPECT_NEAR(std::abs(std::atan2(b->y(), b->x())), a, 1e-9);
}

// The 4 deg/s slew's failing frames: the brightest blobs were pieces (two or three per
// streak, 4-6 px with 1-3 px gaps), and their median set a 5 px streak for 13 px ones.
TEST(StreakShapes, PiecesOfAStreakDoNotSetItsLength) {
  const double L = 13, a = -0.1;
  const Vec2 u(std::cos(a), std::sin(a));
  std::vector<Centroid> stars;
  // Three bright streaks, each broken into two 5.5 px pieces with a 2 px gap (brightest first).
  for (int k = 0; k < 3; ++k) {
    const Vec2 mid(80 + 100 * k, 60 + 90 * k);
    stars.push_back(segment(mid - 3.75 * u, 5.5, a, 1000 - 50 * k));
    stars.push_back(segment(mid + 3.75 * u, 5.5, a, 990 - 50 * k));
  }
  // Two fainter whole ones.
  stars.push_back(segment(Vec2(400, 100), L, a, 500));
  stars.push_back(segment(Vec2(120, 400), L, a, 450));
  const auto b = streakFromShapes(stars, options());
  ASSERT_TRUE(b);
  EXPECT_NEAR(b->norm(), L, 0.5);
}

TEST(StreakShapes, LengthsThatDisagreeGiveNoStreak) {
  // A roll streaks stars by their distance from the boresight: no common length.
  std::vector<Centroid> stars;
  const double lengths[] = {4, 8, 12, 17, 23};
  for (int k = 0; k < 5; ++k) stars.push_back(segment(Vec2(50 + 80 * k, 300), lengths[k], 0.3, 900 - 10 * k));
  EXPECT_FALSE(streakFromShapes(stars, options()));
}

}  // namespace
}  // namespace st
