// solve's celestial frames and --wcs (issue 15 item 4): apparent (annual aberration, plus an
// observer's velocity) or astrometric, a database built in the other frame corrected to the
// request, and a FITS WCS header (TAN, SIP for a distorted camera) read back with cfitsio and
// checked star by star against the truth, both ways, to < 0.1 px.
#include <fitsio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "catalog/epoch_correction.hpp"
#include "catalog/star_catalog.hpp"
#include "catalog/star_database.hpp"
#include "sensors/camera/camera_model.hpp"
#include "tests/app/solve_cli_util.hpp"
#include "tests/app/test_cli_run.hpp"

namespace st {
namespace {

Vec3 boresight(const nlohmann::json& j) { return test::quatOf(j) * Vec3::UnitZ(); }
double arcsecBetween(const Vec3& a, const Vec3& b) {
  return rad2arcsec(std::atan2(a.cross(b).norm(), a.dot(b)));
}

nlohmann::json solveOk(const std::string& args) {
  const auto r = test::runCli("solve --json " + args);
  EXPECT_EQ(r.code, 0) << r.err;
  return nlohmann::json::parse(r.out, nullptr, false);
}

// The frame change is a rotation fitted to the matched stars; the aberration field differs
// from a rotation by its variation over the field, at most |dv|/c x the half-diagonal (the
// 11.4 deg frames: 7.1 deg). So the boresight moves by the aberration at the boresight to
// within that bound, and two databases in different frames agree to within it.
double frameTolArcsec(double dv_km_s) { return dv_km_s / 299792.458 * deg2rad(7.1) * 206264.8; }

TEST(SolveFrames, AstrometricDiffersFromApparentByTheAnnualAberration) {
  const std::string frame = test::shellQuote(test::tetra3Frame());
  const auto app = solveOk("--fov-deg 11.4 " + frame);
  const auto ast = solveOk("--fov-deg 11.4 --no-aberration " + frame);
  EXPECT_EQ(app.at("frame"), "apparent");
  EXPECT_EQ(ast.at("frame"), "astrometric");
  const Vec3 v = earthBarycentricState(app.at("epoch_jyear").get<double>()).velocity_km_s;
  const Vec3 u = boresight(ast);
  const double expected = arcsecBetween(u, applyAberration(u, v));
  EXPECT_GT(expected, 5.0);  // the test means something
  EXPECT_NEAR(arcsecBetween(boresight(app), boresight(ast)), expected, frameTolArcsec(v.norm()));
  const auto& av = app.at("aberration_velocity_km_s");
  EXPECT_NEAR(av[0].get<double>(), v.x(), 1e-9);
  EXPECT_EQ(ast.at("aberration_velocity_km_s")[2], 0.0);
  const auto text = test::runCli("solve --fov-deg 11.4 --no-aberration " + frame);
  EXPECT_NE(text.out.find("frame      astrometric"), std::string::npos) << text.out;
}

TEST(SolveFrames, ObserverVelocityAddsToTheAnnualTerm) {
  const std::string frame = test::shellQuote(test::tetra3Frame());
  const auto app = solveOk("--fov-deg 11.4 " + frame);
  const auto sc = solveOk("--fov-deg 11.4 --observer-velocity-km-s 0 -7.5 0 " + frame);
  const Vec3 ve = earthBarycentricState(app.at("epoch_jyear").get<double>()).velocity_km_s;
  const Vec3 u0 = applyAberration(boresight(app), -ve);  // astrometric boresight
  const double expected = arcsecBetween(applyAberration(u0, ve),
                                        applyAberration(u0, ve + Vec3(0, -7.5, 0)));
  EXPECT_GT(expected, 1.0);
  EXPECT_NEAR(arcsecBetween(boresight(app), boresight(sc)), expected, frameTolArcsec(7.5));
  const auto zero = solveOk("--fov-deg 11.4 --observer-velocity-km-s 0 0 0 " + frame);
  EXPECT_EQ(test::attitudeDifferenceArcsec(app, zero), 0.0);
  auto r = test::runCli("solve --no-aberration --observer-velocity-km-s 1 2 3 " + frame);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--observer-velocity-km-s with --no-aberration"), std::string::npos) << r.err;
  r = test::runCli("solve --observer-velocity-km-s 1 2 4e5 " + frame);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("below the speed of light"), std::string::npos) << r.err;
}

TEST(SolveFrames, DatabaseInTheOtherFrameIsCorrectedToTheRequest) {
  const std::string dir = test::makeTempDir("frames_db");
  const std::string build =
      "catalog build --fov-deg 11.4 --size 1024 768 --epoch 2019.574 --mag-limit 6.5 ";
  ASSERT_EQ(test::runCli(build + "-o " + dir + "/app.db").code, 0);
  ASSERT_EQ(test::runCli(build + "--no-aberration -o " + dir + "/ast.db").code, 0);
  const std::string frame = test::shellQuote(test::tetra3Frame());
  for (const std::string req : {"", "--no-aberration "}) {
    const auto a = solveOk("--fov-deg 11.4 --database " + dir + "/app.db " + req + frame);
    const auto b = solveOk("--fov-deg 11.4 --database " + dir + "/ast.db " + req + frame);
    EXPECT_EQ(a.at("frame"), b.at("frame"));
    EXPECT_EQ(a.at("stars_matched"), b.at("stars_matched"));
    EXPECT_LT(test::attitudeDifferenceArcsec(a, b), frameTolArcsec(30.3)) << req;
  }
}

// ---- --wcs ----

struct Wcs {
  double crval1 = 0, crval2 = 0, crpix1 = 0, crpix2 = 0, cd[2][2] = {};
  int order = 0;
  std::vector<std::vector<double>> a, b, ap, bp;  // [p][q]
  std::string ctype1;
};

std::vector<std::vector<double>> readSip(fitsfile* f, const std::string& name, int order) {
  std::vector<std::vector<double>> c(order + 1, std::vector<double>(order + 1, 0.0));
  for (int p = 0; p <= order; ++p)
    for (int q = 0; p + q <= order; ++q) {
      int status = 0;
      double v = 0;
      const std::string key = name + "_" + std::to_string(p) + "_" + std::to_string(q);
      fits_read_key(f, TDOUBLE, key.c_str(), &v, nullptr, &status);
      if (status == 0) c[p][q] = v;
    }
  return c;
}

Wcs readWcs(const std::string& path) {
  Wcs w;
  fitsfile* f = nullptr;
  int status = 0;
  fits_open_file(&f, path.c_str(), READONLY, &status);
  EXPECT_EQ(status, 0) << path;
  if (status != 0) return w;
  char ctype[FLEN_VALUE] = "";
  fits_read_key(f, TSTRING, "CTYPE1", ctype, nullptr, &status);
  w.ctype1 = ctype;
  fits_read_key(f, TDOUBLE, "CRVAL1", &w.crval1, nullptr, &status);
  fits_read_key(f, TDOUBLE, "CRVAL2", &w.crval2, nullptr, &status);
  fits_read_key(f, TDOUBLE, "CRPIX1", &w.crpix1, nullptr, &status);
  fits_read_key(f, TDOUBLE, "CRPIX2", &w.crpix2, nullptr, &status);
  fits_read_key(f, TDOUBLE, "CD1_1", &w.cd[0][0], nullptr, &status);
  fits_read_key(f, TDOUBLE, "CD1_2", &w.cd[0][1], nullptr, &status);
  fits_read_key(f, TDOUBLE, "CD2_1", &w.cd[1][0], nullptr, &status);
  fits_read_key(f, TDOUBLE, "CD2_2", &w.cd[1][1], nullptr, &status);
  EXPECT_EQ(status, 0);
  int s2 = 0;
  fits_read_key(f, TINT, "A_ORDER", &w.order, nullptr, &s2);
  if (s2 != 0) w.order = 0;
  w.a = readSip(f, "A", w.order);
  w.b = readSip(f, "B", w.order);
  w.ap = readSip(f, "AP", w.order);
  w.bp = readSip(f, "BP", w.order);
  fits_close_file(f, &status);
  return w;
}

double poly(const std::vector<std::vector<double>>& c, double u, double v) {
  double s = 0;
  for (std::size_t p = 0; p < c.size(); ++p)
    for (std::size_t q = 0; q < c[p].size(); ++q) s += c[p][q] * std::pow(u, p) * std::pow(v, q);
  return s;
}

/// The TAN (gnomonic) tangent-plane basis at CRVAL: boresight, east, north.
void tangentBasis(const Wcs& w, Vec3& b, Vec3& e, Vec3& n) {
  const double a = deg2rad(w.crval1), d = deg2rad(w.crval2);
  b = Vec3(std::cos(d) * std::cos(a), std::cos(d) * std::sin(a), std::sin(d));
  e = Vec3(-std::sin(a), std::cos(a), 0);
  n = Vec3(-std::sin(d) * std::cos(a), -std::sin(d) * std::sin(a), std::cos(d));
}

/// FITS pixel (1-based) -> direction.
Vec3 pixelToSky(const Wcs& w, double x, double y) {
  const double u = x - w.crpix1, v = y - w.crpix2;
  const double uu = u + poly(w.a, u, v), vv = v + poly(w.b, u, v);
  const double xi = deg2rad(w.cd[0][0] * uu + w.cd[0][1] * vv);
  const double eta = deg2rad(w.cd[1][0] * uu + w.cd[1][1] * vv);
  Vec3 b, e, n;
  tangentBasis(w, b, e, n);
  return (b + xi * e + eta * n).normalized();
}

/// Direction -> FITS pixel (with AP/BP).
Vec2 skyToPixel(const Wcs& w, const Vec3& d) {
  Vec3 b, e, n;
  tangentBasis(w, b, e, n);
  const double xi = rad2deg(d.dot(e) / d.dot(b)), eta = rad2deg(d.dot(n) / d.dot(b));
  const double det = w.cd[0][0] * w.cd[1][1] - w.cd[0][1] * w.cd[1][0];
  const double uu = (w.cd[1][1] * xi - w.cd[0][1] * eta) / det;
  const double vv = (-w.cd[1][0] * xi + w.cd[0][0] * eta) / det;
  return Vec2(w.crpix1 + uu + poly(w.ap, uu, vv), w.crpix2 + vv + poly(w.bp, uu, vv));
}

struct TrueStar {
  Vec3 u;
  Vec2 px;
};

/// A star list of the catalog's stars seen by `cam` at `q_ic` (astrometric, epoch 2020).
std::vector<TrueStar> writeStarList(const CameraModel& cam, const Quat& q_ic, const std::string& path) {
  const StarCatalog cat = loadCatalog(StarDatabase::defaultCatalogPath());
  std::vector<TrueStar> stars;
  std::ofstream f(path);
  f << "x,y,flux\n";
  for (const CatalogEntry& e : cat.entries) {
    if (e.vmag > 6.0) continue;
    const Vec3 u = apparentDirection(e, cat.epoch_jyear, 2020.0, true, false);
    const Vec3 v = q_ic.conjugate() * u;
    if (v.z() <= 0 || !cam.isVectorInImage(v, 3)) continue;
    const Vec2 px = *cam.vectorToPixel(v);
    f << px.x() << "," << px.y() << "," << 1e6 * std::pow(10.0, -0.4 * e.vmag) << "\n";
    stars.push_back({u, px});
  }
  return stars;
}

void checkWcsRoundTrip(const Distortion& dist, const std::string& ctype) {
  const std::string dir = test::makeTempDir("wcs");
  const CameraModel cam(1024, 768, 2600, 2610, 515.0, 380.0, dist);
  cam.saveYaml(dir + "/cam.yaml");
  const Quat q = attitudeFromRaDecRoll({deg2rad(83.0), deg2rad(-2.0), deg2rad(25.0)});  // Orion
  const auto stars = writeStarList(cam, q, dir + "/stars.csv");
  ASSERT_GE(stars.size(), 15u);
  const auto r = test::runCli("solve --json --camera " + dir + "/cam.yaml --no-aberration --epoch "
                              "2020.0 --width 1024 --height 768 --wcs " + dir + "/out.wcs " +
                              dir + "/stars.csv");
  ASSERT_EQ(r.code, 0) << r.err;
  const Wcs w = readWcs(dir + "/out.wcs");
  EXPECT_EQ(w.ctype1, ctype);
  const double scale = cam.pixelScale();
  double worst_sky = 0, worst_px = 0;
  for (const TrueStar& s : stars) {
    worst_sky = std::max(worst_sky, std::acos(std::min(1.0, pixelToSky(w, s.px.x() + 1, s.px.y() + 1).dot(s.u))) / scale);
    worst_px = std::max(worst_px, (skyToPixel(w, s.u) - (s.px + Vec2(1, 1))).norm());
  }
  EXPECT_LT(worst_sky, 0.1) << "pixel -> sky [px]";
  EXPECT_LT(worst_px, 0.1) << "sky -> pixel [px]";
}

TEST(SolveWcs, TanHeaderMapsEveryStarBothWaysWithinATenthOfAPixel) {
  checkWcsRoundTrip(Distortion{}, "RA---TAN");
}

TEST(SolveWcs, SipHeaderCarriesTheCamerasDistortion) {
  Distortion d;
  d.k1 = -0.15;  // corners move by ~6 px: far beyond the tolerance without SIP
  d.k2 = 0.08;
  checkWcsRoundTrip(d, "RA---TAN-SIP");
}

TEST(SolveWcs, BadWcsPathIsExitTwoBeforeAnyWork) {
  const auto r = test::runCli("solve --fov-deg 11.4 --wcs /proc/no/such.wcs " +
                              test::shellQuote(test::tetra3Frame()));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--wcs"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace st
