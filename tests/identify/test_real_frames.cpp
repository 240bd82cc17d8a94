// End-to-end on the eight real tetra3 frames (1024x768, 16-bit TIFF, ~11.4 deg HFOV):
// detection -> lost-in-space identification with the focal length unknown (FOV search
// 5-30 deg) -> fitted camera. Each frame must be solved with >= 10 stars matched and an
// RMS residual below 1 px; Alt40_Azi-135 must point near RA 230.7, Dec +11.0 (data README).
#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "common/conventions.hpp"
#include "sensors/detect/star_detector.hpp"
#include "sensors/identify/fov_search.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

const StarDatabase& realFrameDatabase(double max_pair_angle) {
  static const StarDatabase db = [&] {
    const StarCatalog cat = loadCatalog(test::hipparcosSubsetPath());
    DatabaseParams p{};
    p.max_pair_angle = max_pair_angle;
    p.mag_limit = 7.0;       // everything in the committed subset (V <~ 6.6)
    p.epoch_jyear = 2019.57;  // the frames were taken 2019-07-29
    p.aberration = true;
    p.parallax = true;
    p.double_star_sep = arcsec2rad(60.0);  // ~1.5 px
    p.max_stars_per_region = 0;
    p.neighbour_radius = deg2rad(8.0);
    return StarDatabase::build(cat, p);
  }();
  return db;
}

TEST(RealFrames, AllEightSolvedFromTheImageAlone) {
  const auto files = test::tetra3Frames();
  ASSERT_EQ(files.size(), 8u) << test::tetra3ImageDir();
  const double min_hfov = deg2rad(5.0), max_hfov = deg2rad(30.0), scale_tol = 0.02;
  const auto grid = fovSearchGrid(min_hfov, max_hfov, scale_tol);
  const double max_pair =
      2 * CameraModel::fromFov(1024, 768, grid.back()).halfDiagonalFov() * (1 + scale_tol);
  const StarDatabase& db = realFrameDatabase(max_pair);
  auto id = StarIdentifier::create("pyramid");
  for (const std::string& f : files) {
    SCOPED_TRACE(f);
    const cv::Mat img = cv::imread(f, cv::IMREAD_ANYDEPTH | cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(img.empty());
    const DetectionResult det = detectStars(img);
    ASSERT_TRUE(det.reason.empty()) << det.reason;
    const FovSearchResult r =
        identifyUnknownFov(det.stars, img.cols, img.rows, db, *id, grid, scale_tol, 0.5);
    const RaDecRoll rdr = raDecRollFromAttitude(r.result.q_ic);
    std::printf("%s: %s, %zu/%zu matched, RMS %.3f px, HFOV %.3f deg, RA %.3f Dec %.3f, "
                "P_false %.2g, %d FOVs, %.1f ms\n",
                std::filesystem::path(f).filename().c_str(),
                r.result.solved() ? "solved" : r.result.reason.c_str(), r.result.matches.size(),
                det.stars.size(), r.result.rms_residual_px, rad2deg(r.camera.horizontalFov()),
                rad2deg(rdr.ra), rad2deg(rdr.dec), r.result.false_match_probability,
                r.fovs_tried, r.search_ms);
    ASSERT_TRUE(r.result.solved()) << r.result.reason;
    EXPECT_GE(r.result.matches.size(), 10u);
    EXPECT_LT(r.result.rms_residual_px, 1.0);
    EXPECT_NEAR(rad2deg(r.camera.horizontalFov()), 11.4, 0.3);
    if (f.find("Alt40_Azi-135") != std::string::npos) {
      EXPECT_NEAR(rad2deg(rdr.ra), 230.7, 0.2);
      EXPECT_NEAR(rad2deg(rdr.dec), 11.0, 0.2);
    }
  }
}

}  // namespace
}  // namespace st
