// Unit tests with analytic answers: observation sigmas, the binomial tail, triangle
// features (seed 001 eq. 2-12), the registry.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "common/conventions.hpp"
#include "sensors/identify/identifier.hpp"
#include "sensors/identify/triangle_features.hpp"
#include "sensors/identify/verify.hpp"

namespace st {
namespace {

TEST(StarObservation, CentreSigmaIsPixelSigmaTimesScale) {
  const CameraModel cam = CameraModel::fromFov(1000, 1000, deg2rad(10.0));
  Centroid c;
  c.px = Vec2(cam.cx(), cam.cy());
  c.cov_px = 0.04 * Mat2::Identity();  // 0.2 px
  const auto obs = toStarObservations({c}, cam);
  ASSERT_EQ(obs.size(), 1u);
  EXPECT_NEAR(obs[0].v_cam.z(), 1.0, 1e-12);
  EXPECT_NEAR(obs[0].sigma, 0.2 / cam.fx(), 1e-12);
  c.cov_px.setZero();  // floor
  EXPECT_NEAR(toStarObservations({c}, cam, 0.05)[0].sigma, 0.05 * cam.pixelScale(), 1e-15);
}

TEST(Verify, BinomialUpperTail) {
  EXPECT_DOUBLE_EQ(binomialUpperTail(10, 0, 0.3), 1.0);
  EXPECT_NEAR(binomialUpperTail(3, 3, 0.5), 0.125, 1e-15);
  EXPECT_NEAR(binomialUpperTail(4, 2, 0.5), 11.0 / 16.0, 1e-14);
  // C(20,5) p^5 q^15 + C(20,6) p^6 q^14 + ... (later terms < 1e-19)
  const double p = 1e-3, q = 1 - p;
  const double exact = 15504 * std::pow(p, 5) * std::pow(q, 15) +
                       38760 * std::pow(p, 6) * std::pow(q, 14) +
                       77520 * std::pow(p, 7) * std::pow(q, 13);
  EXPECT_NEAR(binomialUpperTail(20, 5, p) / exact, 1.0, 1e-8);
  EXPECT_EQ(binomialUpperTail(5, 6, 0.5), 0.0);
}

TEST(TriangleFeatures, OctantAndSmallTriangle) {
  // The octant triangle: spherical area pi/2 (L'Huilier, eq. 8).
  const TriangleFeature s = sphericalTriangle(Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ(), 3);
  EXPECT_NEAR(s.area, kPi / 2, 1e-12);
  // Its planar chord triangle is equilateral with side sqrt(2): area sqrt(3)/4 * 2 (eq. 2).
  const TriangleFeature p = planarTriangle(Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ());
  EXPECT_NEAR(p.area, std::sqrt(3.0) / 2, 1e-12);
  EXPECT_NEAR(p.polar_moment, p.area * 6.0 / 36.0, 1e-12);  // eq. 7
  // A small triangle: spherical -> planar; the polar moment of a planar triangle about its
  // centroid is A (a^2 + b^2 + c^2) / 36 (eq. 7), which eq. 12 must approach.
  const double e = 1e-3;
  const Vec3 a = Vec3(0, 0, 1), b = Vec3(e, 0, 1).normalized(), c = Vec3(0, 2 * e, 1).normalized();
  const TriangleFeature ps = planarTriangle(a, b, c), ss = sphericalTriangle(a, b, c, 4);
  EXPECT_NEAR(ss.area / ps.area, 1.0, 1e-5);
  EXPECT_NEAR(ss.polar_moment / ps.polar_moment, 1.0, 0.01);
}

TEST(IdentifierRegistry, NamesCreateAndUnknown) {
  const auto names = StarIdentifier::names();
  // The library's table first, in order (default first); members registered by this test
  // executable (registered_in_test_identifier.cpp) follow.
  const std::vector<std::string> lib = {"pyramid", "voting", "liebe", "planar", "spherical",
                                        "nvertex"};
  ASSERT_GE(names.size(), lib.size());
  EXPECT_EQ(std::vector<std::string>(names.begin(), names.begin() + lib.size()), lib);
  EXPECT_EQ(names.front(), StarIdentifier::defaultName());
  for (const auto& n : names) {
    auto id = StarIdentifier::create(n);
    ASSERT_TRUE(id) << n;
    EXPECT_EQ(id->name(), n);
    EXPECT_NE(StarIdentifier::help().find(n + ": "), std::string::npos) << n;
  }
  std::string err;
  EXPECT_FALSE(StarIdentifier::create("tetra", {}, &err));
  EXPECT_NE(err.find("pyramid"), std::string::npos);
}

// Validation once, at construction: an unknown solver name or a bad tolerance is refused by
// create() with the field named (it used to come back from every identify() as NoMatch).
TEST(IdentifierRegistry, InvalidOptionsRefusedAtConstruction) {
  const std::vector<std::pair<std::string, IdentifyOptions>> cases = [] {
    std::vector<std::pair<std::string, IdentifyOptions>> c;
    IdentifyOptions o;
    o.solver = "nope";
    c.push_back({"IdentifyOptions.solver", o});
    o = {};
    o.pair_sigma = 0;
    c.push_back({"IdentifyOptions.pair_sigma", o});
    o = {};
    o.max_stars = 2;
    c.push_back({"IdentifyOptions.max_stars", o});
    o = {};
    o.verify.gate_sigma = -1;
    c.push_back({"VerifyOptions.gate_sigma", o});
    o = {};
    o.verify.min_matches = 2;
    c.push_back({"VerifyOptions.min_matches", o});
    return c;
  }();
  for (const auto& [field, o] : cases) {
    std::string err;
    EXPECT_FALSE(o.isValid(&err)) << field;
    EXPECT_NE(err.find(field), std::string::npos) << err;
    for (const auto& n : StarIdentifier::names()) {
      err.clear();
      EXPECT_EQ(StarIdentifier::create(n, o, &err), nullptr) << n << " " << field;
      EXPECT_NE(err.find(field), std::string::npos) << err;
    }
  }
  std::string err;
  EXPECT_TRUE(IdentifyOptions{}.isValid(&err)) << err;
  EXPECT_TRUE(err.empty());
}

}  // namespace
}  // namespace st
