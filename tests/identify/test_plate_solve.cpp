// The plate-solver habits of sensors/identify/plate_solve: mirrored centroids, the position
// hint's distance, and the order and limits of the parity search (without a database: the
// search is a stub that records what it was given).
#include <gtest/gtest.h>

#include "common/conventions.hpp"
#include "sensors/identify/plate_solve.hpp"

namespace st {
namespace {

std::vector<Centroid> threeStars() {
  std::vector<Centroid> c(3);
  c[0].px = Vec2(10, 20);
  c[1].px = Vec2(511.5, 5);
  c[2].px = Vec2(1000.25, 700);
  c[2].cov_px << 0.04, 0.01, 0.01, 0.09;
  return c;
}

TEST(PlateSolve, MirrorIsAboutTheCentreOfThePixelGridAndItsOwnInverse) {
  const auto c = threeStars();
  const auto m = mirrorLeftRight(c, 1024);
  EXPECT_DOUBLE_EQ(m[0].px.x(), 1013);
  EXPECT_DOUBLE_EQ(m[1].px.x(), 511.5);  // the centre column stays
  EXPECT_DOUBLE_EQ(m[2].px.y(), 700);
  EXPECT_DOUBLE_EQ(m[2].cov_px(0, 1), -0.01);  // x -> -x flips the correlation
  EXPECT_DOUBLE_EQ(m[2].cov_px(1, 1), 0.09);
  const auto back = mirrorLeftRight(m, 1024);
  for (std::size_t i = 0; i < c.size(); ++i) {
    EXPECT_EQ(back[i].px, c[i].px);
    EXPECT_EQ(back[i].cov_px, c[i].cov_px);
  }
}

TEST(PlateSolve, BoresightDistanceAndHintRefusal) {
  const Quat q = attitudeFromRaDecRoll({deg2rad(230.7), deg2rad(11.0), deg2rad(-27.7)});
  EXPECT_NEAR(rad2deg(boresightDistance(q, {deg2rad(230.7), deg2rad(11.0), 0.1})), 0, 1e-9);
  EXPECT_NEAR(rad2deg(boresightDistance(q, {deg2rad(230.7), deg2rad(13.0), 0.1})), 2.0, 1e-9);
  IdentifyResult r;
  r.q_ic = q;
  EXPECT_EQ(refuseOutsideHint({deg2rad(230.7), deg2rad(13.0), deg2rad(2.1)})(r), "");
  const std::string why = refuseOutsideHint({deg2rad(230.7), deg2rad(13.0), deg2rad(1.9)})(r);
  EXPECT_NE(why.find("2.00 deg from the position hint (radius 1.90 deg)"), std::string::npos) << why;
}

struct StubSearch {
  std::vector<double> first_x;  ///< x of the first centroid of each call
  bool solve_mirrored = false;
  FovSearchResult operator()(const std::vector<Centroid>& c) {
    first_x.push_back(c[0].px.x());
    FovSearchResult r;
    const bool mirrored = c[0].px.x() != 10;
    if (mirrored == solve_mirrored) r.result.status = IdentifyStatus::Solved;
    r.result.reason = mirrored ? "m" : "n";
    return r;
  }
};

TEST(PlateSolve, NormalParityFirstAndTheMirrorOnlyWhenItFails) {
  StubSearch normal;
  auto r = solveBothParities(threeStars(), 1024, ParityChoice::Both, {}, std::ref(normal));
  EXPECT_TRUE(r.search.result.solved());
  EXPECT_EQ(r.parity, Parity::Normal);
  EXPECT_EQ(normal.first_x, std::vector<double>{10});

  StubSearch mirrored;
  mirrored.solve_mirrored = true;
  r = solveBothParities(threeStars(), 1024, ParityChoice::Both, {}, std::ref(mirrored));
  EXPECT_TRUE(r.search.result.solved());
  EXPECT_EQ(r.parity, Parity::Flipped);
  EXPECT_EQ(r.parities_tried, 2);
  EXPECT_EQ(mirrored.first_x, (std::vector<double>{10, 1013}));

  StubSearch only_normal;
  only_normal.solve_mirrored = true;
  r = solveBothParities(threeStars(), 1024, ParityChoice::Normal, {}, std::ref(only_normal));
  EXPECT_FALSE(r.search.result.solved());
  EXPECT_EQ(r.parities_tried, 1);
}

TEST(PlateSolve, BothFailingNamesBothReasonsAndAnExpiredDeadlineStopsTheRetry) {
  StubSearch never;
  never.solve_mirrored = true;
  auto fails = [&](const std::vector<Centroid>& c) {
    FovSearchResult r = never(c);
    r.result.status = IdentifyStatus::NoMatch;
    return r;
  };
  auto r = solveBothParities(threeStars(), 1024, ParityChoice::Both, {}, fails);
  EXPECT_EQ(r.search.result.reason, "normal parity: n; flipped parity: m");
  SearchLimits expired;
  expired.deadline = std::chrono::steady_clock::now() - std::chrono::seconds(1);
  never.first_x.clear();
  r = solveBothParities(threeStars(), 1024, ParityChoice::Both, expired, fails);
  EXPECT_EQ(never.first_x.size(), 1u);  // the first search itself checks the deadline
  EXPECT_TRUE(r.search.cpu_limit_reached);
  EXPECT_EQ(r.search.result.reason, kCpuLimitReason);
}

}  // namespace
}  // namespace st
