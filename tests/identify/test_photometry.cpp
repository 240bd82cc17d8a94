// Photometry (sensors/identify/photometry.hpp): the instrument-magnitude law, the robust fit
// of zero point, colour term and off-axis exponent, the eight real tetra3 frames (fitted
// magnitudes agree with catalog V within the reported scatter) and simulated frames whose
// zero point is known from the renderer's flux law (sensors/sim/sensor_params.hpp eq. 3.4).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

#include <opencv2/imgcodecs.hpp>

#include "common/conventions.hpp"
#include "sensors/detect/star_detector.hpp"
#include "sensors/identify/fov_search.hpp"
#include "sensors/identify/photometry.hpp"
#include "sensors/sim/detector.hpp"
#include "sensors/sim/star_renderer.hpp"
#include "sensors/sim/star_source.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

TEST(Photometry, InstrumentMagnitudeIsPogsonPerSecond) {
  EXPECT_DOUBLE_EQ(instrumentMagnitude(100.0, 1.0), -5.0);
  // Ten times the exposure, ten times the flux: the same magnitude.
  EXPECT_NEAR(instrumentMagnitude(1000.0, 10.0), -5.0, 1e-12);
  EXPECT_NEAR(instrumentMagnitude(100.0, 0.1) - instrumentMagnitude(100.0, 1.0), -2.5, 1e-12);
  EXPECT_TRUE(std::isnan(instrumentMagnitude(0.0, 1.0)));
  EXPECT_TRUE(std::isnan(instrumentMagnitude(10.0, 0.0)));
  EXPECT_DOUBLE_EQ(offAxisRegressor(0.0), 0.0);
  EXPECT_NEAR(offAxisRegressor(deg2rad(60.0)), 2.5 * std::log10(0.5), 1e-12);
}

/// Synthetic stars: V = m_inst + zp + c (B-V) + n 2.5 log10 cos(theta) + noise.
std::vector<PhotometryStar> synthetic(int n, double zp, double c, double expo, double noise,
                                      double max_theta, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> uv(1.0, 6.0), ubv(-0.2, 1.6), ur(0.0, 1.0);
  std::normal_distribution<double> n01;
  std::vector<PhotometryStar> s(n);
  for (auto& x : s) {
    x.catalog_v = uv(rng);
    x.bv = ubv(rng);
    x.off_axis = max_theta * std::sqrt(ur(rng));
    x.m_inst = x.catalog_v - zp - c * x.bv - expo * offAxisRegressor(x.off_axis) + noise * n01(rng);
  }
  return s;
}

TEST(Photometry, FitRecoversZeroPointColourAndExponentWithinTheirErrors) {
  std::mt19937_64 rng(7);
  auto stars = synthetic(400, 12.3, -0.25, 4.0, 0.05, deg2rad(40.0), rng);
  // Outliers (a blended pair, a variable star): clipped, not followed.
  for (int k = 0; k < 10; ++k) stars[k].m_inst -= 1.5;
  stars[10].bv = std::numeric_limits<double>::quiet_NaN();
  const PhotometryFit f = fitPhotometry(stars);
  ASSERT_TRUE(f.ok) << f.reason;
  ASSERT_TRUE(f.colour_fitted);
  ASSERT_TRUE(f.off_axis_fitted);
  EXPECT_NEAR(f.zero_point, 12.3, 4 * f.zero_point_se);
  EXPECT_NEAR(f.colour_term, -0.25, 4 * f.colour_term_se);
  EXPECT_NEAR(f.off_axis_exponent, 4.0, 4 * f.off_axis_se);
  EXPECT_NEAR(f.scatter, 0.05, 0.01);
  EXPECT_NEAR(f.robust_sigma, 0.05, 0.01);
  EXPECT_GE(f.clipped, 10);
  for (int k = 0; k < 10; ++k) EXPECT_FALSE(f.kept[k]);
  // The standard error is the one of 390 stars of 0.05 mag (ZP at B-V = 0 extrapolates).
  EXPECT_LT(f.zero_point_se, 0.02);
}

TEST(Photometry, NarrowFieldFixesTheExponentAndFewColoursNoColourTerm) {
  std::mt19937_64 rng(8);
  auto stars = synthetic(30, 5.0, 0.0, 4.0, 0.1, deg2rad(7.0), rng);
  for (std::size_t k = 3; k < stars.size(); ++k)
    stars[k].bv = std::numeric_limits<double>::quiet_NaN();
  PhotometryOptions o;
  o.off_axis_exponent = 4.0;
  const PhotometryFit f = fitPhotometry(stars, o);
  ASSERT_TRUE(f.ok);
  EXPECT_FALSE(f.off_axis_fitted);  // SE of n over 7 deg with 0.1 mag noise is ~ 10
  EXPECT_FALSE(f.colour_fitted);    // 3 known colours < min_colour_stars
  EXPECT_EQ(f.off_axis_exponent, 4.0);
  EXPECT_NEAR(f.zero_point, 5.0, 4 * f.zero_point_se);
}

TEST(Photometry, TooFewUsableStarsIsNotAFit) {
  std::mt19937_64 rng(9);
  auto stars = synthetic(4, 5.0, 0.0, 0.0, 0.1, 0.1, rng);
  stars[0].usable = stars[1].usable = false;
  const PhotometryFit f = fitPhotometry(stars);
  EXPECT_FALSE(f.ok);
  EXPECT_NE(f.reason.find("2 usable stars"), std::string::npos) << f.reason;
}

// ---- the eight real frames -----------------------------------------------------------------

const StarCatalog& hipparcosSubset() {
  static const StarCatalog cat = loadCatalog(test::hipparcosSubsetPath());
  return cat;
}

std::function<double(uint32_t)> bvLookup() {
  static const std::map<uint32_t, double> bv = [] {
    std::map<uint32_t, double> m;
    for (const CatalogEntry& e : hipparcosSubset().entries) m[e.id] = e.bv;
    return m;
  }();
  return [](uint32_t id) {
    const auto it = bv.find(id);
    return it == bv.end() ? std::numeric_limits<double>::quiet_NaN() : it->second;
  };
}

const StarDatabase& realFrameDatabase(double max_pair_angle) {
  static const StarDatabase db = [&] {
    DatabaseParams p{};
    p.max_pair_angle = max_pair_angle;
    p.mag_limit = 7.0;
    p.epoch_jyear = 2019.57;
    p.aberration = true;
    p.parallax = true;
    p.double_star_sep = arcsec2rad(60.0);
    p.max_stars_per_region = 0;
    p.neighbour_radius = deg2rad(8.0);
    return StarDatabase::build(hipparcosSubset(), p);
  }();
  return db;
}

// Acceptance (issue 17 item 4): |V - fitted| < 3 x the scatter each frame's fit reports for
// >= 95 % of the identified stars the fits could use, over the eight frames (170 stars; a
// frame of 14 stars cannot show 95 %). Saturated stars are listed, not fitted (their flux is
// clipped). The exposure of the frames is not known: t = 1 s, the zero point absorbs it. The
// frames share one camera and exposure: their zero points and colour terms must agree.
TEST(Photometry, RealFramesFittedMagnitudesAgreeWithCatalogV) {
  const auto files = test::tetra3Frames();
  ASSERT_EQ(files.size(), 8u);
  const double scale_tol = 0.02;
  const auto grid = fovSearchGrid(deg2rad(10.0), deg2rad(13.0), scale_tol);
  const double max_pair =
      2 * CameraModel::fromFov(1024, 768, grid.back()).halfDiagonalFov() * (1 + scale_tol);
  const StarDatabase& db = realFrameDatabase(max_pair);
  auto id = StarIdentifier::create("pyramid");
  int total = 0, inside = 0;
  std::vector<double> zps, zp_w, colours;
  for (const std::string& file : files) {
    SCOPED_TRACE(file);
    const cv::Mat img = cv::imread(file, cv::IMREAD_ANYDEPTH | cv::IMREAD_GRAYSCALE);
    const DetectionResult det = detectStars(img);
    const FovSearchResult r =
        identifyUnknownFov(det.stars, img.cols, img.rows, db, *id, grid, scale_tol, 0.5);
    ASSERT_TRUE(r.result.solved()) << r.result.reason;
    const auto stars = photometryStars(det.stars, r.obs, r.result.matches, db, 1.0, bvLookup());
    const PhotometryFit f = fitPhotometry(stars);
    ASSERT_TRUE(f.ok) << f.reason;
    int n = 0, in = 0;
    for (std::size_t k = 0; k < stars.size(); ++k) {
      if (!stars[k].usable) continue;
      ++n;
      if (std::abs(f.residual[k]) < 3 * f.scatter) ++in;
    }
    std::printf("%s: %zu identified, %d usable, ZP %.3f +- %.3f, c %s%.3f +- %.3f, n %.2f%s, "
                "scatter %.3f mag (RMS %.3f), %d clipped, %d/%d within 3 sigma\n",
                file.substr(file.rfind('/') + 1).c_str(), stars.size(), n, f.zero_point,
                f.zero_point_se, f.colour_fitted ? "" : "(not fitted) ", f.colour_term,
                f.colour_term_se, f.off_axis_exponent, f.off_axis_fitted ? " (fitted)" : " (fixed)",
                f.scatter, f.rms, f.clipped, in, n);
    EXPECT_GE(in, 0.85 * n);
    EXPECT_LT(f.scatter, 0.25);
    total += n;
    inside += in;
    zps.push_back(f.zero_point);
    zp_w.push_back(1 / (f.zero_point_se * f.zero_point_se));
    if (f.colour_fitted) colours.push_back(f.colour_term);
  }
  std::printf("all frames: %d/%d within 3 sigma\n", inside, total);
  EXPECT_GE(inside, 0.95 * total);
  // One camera: the eight zero points scatter like their standard errors (chi-square with 7
  // degrees of freedom below its 0.1 % point, 24.3), the colour term is the detector's.
  double sw = 0, swz = 0;
  for (std::size_t k = 0; k < zps.size(); ++k) sw += zp_w[k], swz += zp_w[k] * zps[k];
  double chi2 = 0;
  for (std::size_t k = 0; k < zps.size(); ++k) chi2 += zp_w[k] * std::pow(zps[k] - swz / sw, 2);
  std::printf("zero point %.3f +- %.3f over 8 frames, chi2 %.1f (7 dof)\n", swz / sw,
              1 / std::sqrt(sw), chi2);
  EXPECT_LT(chi2, 24.3);
  ASSERT_EQ(colours.size(), 8u);
  for (double c : colours) EXPECT_GT(c, 0.0);  // an unfiltered CCD sees red stars brighter
}

// ---- simulated frames with a known zero point ----------------------------------------------

// The renderer makes F0 10^(-0.4 V) (pi D^2 / 4) T QE t electrons, so the flux per second in
// ADU is 10^(-0.4 V) K with K = F0 (pi D^2 / 4) T QE / gain and ZP = 2.5 log10 K. The fitted
// ZP must agree within 3 of its standard errors; a flux law without the exposure (or with
// another base) misses it by 2.5 log10(1 / 0.1) = 2.5 mag.
TEST(Photometry, SimulatedFramesRecoverTheRenderersZeroPoint) {
  const CameraModel cam = CameraModel::fromFov(800, 600, deg2rad(16.0));
  static const StarDatabase db = [&] {
    DatabaseParams p{};
    p.max_pair_angle = 2 * cam.halfDiagonalFov() + deg2rad(0.5);
    p.mag_limit = 6.5;
    p.epoch_jyear = 2020.0;
    p.double_star_sep = arcsec2rad(10.0);
    p.neighbour_radius = deg2rad(5.0);
    return StarDatabase::build(hipparcosSubset(), p);
  }();
  SensorParams sp;
  sp.bit_depth = 12;
  sp.exposure_s = 0.1;
  sp.psf_sigma_px = 1.0;
  sp.aperture_diameter_m = 0.03;
  const double K = sp.v0_photon_flux * 0.25 * kPi * sp.aperture_diameter_m *
                   sp.aperture_diameter_m * sp.transmission * sp.qe / sp.gain();
  const double zp_true = 2.5 * std::log10(K);
  const DatabaseStarSource source(db);
  const StarRenderer renderer(cam, sp, source);
  const Detector detector(sp, cam.width(), cam.height());
  DetectorOptions dopt;
  dopt.gain_e_per_adu = sp.gain();
  dopt.read_noise_adu = sp.read_noise_e / sp.gain();
  std::mt19937_64 rng(2026);
  std::normal_distribution<double> n01;
  std::vector<PhotometryStar> stars;
  std::vector<StarMatch> none;
  for (int frame = 0; frame < 6; ++frame) {
    Quat q(n01(rng), n01(rng), n01(rng), n01(rng));
    q.normalize();
    cv::Mat e = detector.meanBackground().clone();
    const auto truth = renderer.render([&](double) { return q; }, e);
    const cv::Mat img = detector.expose(e, rng);
    const DetectionResult det = detectStars(img, dopt);
    for (const Centroid& c : det.stars) {
      const TrueStar* best = nullptr;
      for (const TrueStar& t : truth)
        if ((t.px - c.px).norm() < 1.0) best = &t;
      if (!best) continue;
      PhotometryStar s;
      s.m_inst = instrumentMagnitude(c.flux, sp.exposure_s);
      const Vec3 v = cam.pixelToVector(c.px);
      s.off_axis = std::atan2(v.head<2>().norm(), v.z());
      s.catalog_v = best->mag;
      s.bv = std::numeric_limits<double>::quiet_NaN();
      s.usable = (c.flags & (kSaturated | kTouchesEdge)) == 0;
      stars.push_back(s);
    }
  }
  PhotometryOptions o;
  o.fit_off_axis = false;
  o.off_axis_exponent = 0.0;  // the renderer has no vignetting
  const PhotometryFit f = fitPhotometry(stars, o);
  ASSERT_TRUE(f.ok) << f.reason;
  std::printf("simulated: %d stars used (%d clipped), ZP %.4f +- %.4f, true %.4f, scatter %.3f\n",
              f.used, f.clipped, f.zero_point, f.zero_point_se, zp_true, f.scatter);
  EXPECT_GE(f.used, 30);
  EXPECT_NEAR(f.zero_point, zp_true, 3 * f.zero_point_se);
}

}  // namespace
}  // namespace st
