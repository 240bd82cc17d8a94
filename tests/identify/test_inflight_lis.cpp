// Lost-in-space on simulated in-flight frames with radiation hits (issue 34): an 18 deg
// camera with rows binned 2x, 8-bit, a sparse sky (the catalog to V 6.6), and 0-100 hits per
// frame from a particle flux. The acceptance: no wrong attitude over 1,000 frames; and the
// hit rule has teeth: without it (DetectorOptions::flag_hits = false) frames with 40 hits
// that it solves fail or are misidentified.
#include <gtest/gtest.h>

#include <cstdio>

#include "sensors/detect/star_detector.hpp"
#include "sensors/identify/plate_solve.hpp"
#include "tests/detect/inflight_frame.hpp"

namespace st {
namespace {

// [arcsec] a boresight farther than this from the truth's is a wrong attitude (the pixel is
// 90-180"; a misidentification is degrees off).
constexpr double kWrongArcsec = 60;

struct Outcome {
  bool solved = false;
  double error_arcsec = 0;
  double nees = 0;  ///< the error's squared Mahalanobis distance under the reported covariance
  int matches = 0;
};

Outcome solveFrame(const test::InflightFrame& f, const StarDatabase& db, bool rule) {
  DetectorOptions o;
  o.flag_hits = rule;
  o.pixel_aspect = test::inflightCamera().pixelAspect();  // as solve and the tracker set it
  const DetectionResult det = detectStars(f.image, o);
  static const auto id = StarIdentifier::create(StarIdentifier::defaultName());
  LostInSpaceCameras cams;
  cams.camera = test::inflightCamera();
  const PlateSolveResult r = lostInSpace(det.stars, f.image.cols, f.image.rows, db, *id, cams,
                                         0.1, ParityChoice::Normal);
  Outcome out;
  out.solved = r.search.result.solved();
  if (out.solved) {
    const IdentifyResult& res = r.search.result;
    // Where the camera points (the Swarm frames' criterion: the centre against the truth's).
    const Vec3 z_est = res.q_ic * Vec3::UnitZ(), z_true = f.q_ib * Vec3::UnitZ();
    out.error_arcsec = rad2arcsec(std::atan2(z_est.cross(z_true).norm(), z_est.dot(z_true)));
    // Error as a rotation in the camera frame: q_true = q_est (x) Exp(e).
    const Vec3 e = quatLog(canonical(res.q_ic.inverse() * f.q_ib));
    out.nees = e.dot(res.cov_cam.ldlt().solve(e));
    out.matches = static_cast<int>(res.matches.size());
  }
  return out;
}

TEST(InflightLis, StatisticalThousandFramesWithHitsGiveNoWrongAttitude) {
  const auto db = test::inflightDatabase();
  const test::InflightSimulator sim(*db);
  int solved = 0, wrong = 0, frames = 0, clean_solved = 0;
  double worst = 0;
  for (uint64_t seed = 1; seed <= 1000; ++seed) {
    const double mean_hits = static_cast<double>(seed % 101);  // 0..100
    const test::InflightFrame f = sim.frame(seed, mean_hits);
    const Outcome o = solveFrame(f, *db, true);
    ++frames;
    clean_solved += solveFrame(sim.frame(seed, 0), *db, true).solved;  // the same sky, no hits
    if (!o.solved) continue;
    ++solved;
    worst = std::max(worst, o.error_arcsec);
    if (o.error_arcsec > kWrongArcsec) {
      ++wrong;
      std::printf("  wrong: seed %llu, %zu hits, error %.0f\", NEES %.1f, %d stars\n",
                  static_cast<unsigned long long>(seed), f.hits.size(), o.error_arcsec, o.nees,
                  o.matches);
    }
  }
  std::printf("%d frames: %d solved (%d without hits), %d wrong, worst boresight error %.1f\"\n",
              frames, solved, clean_solved, wrong, worst);
  EXPECT_EQ(wrong, 0);
  // Hits the rule cannot tell (a corner dot, a bent track: light on every side of the peak)
  // rank among the stars, and every blob raises the chance that a random match verifies,
  // so a sparse sky under 60-100 bright hits is sometimes left unsolved: measured 874 of
  // 1,000 (all 1,000 without hits). Unsolved is the safe failure; the floor keeps it so.
  EXPECT_GE(solved, 8 * clean_solved / 10);
}

TEST(InflightLis, WithoutTheHitRuleFramesWithFortyHitsFailOrAreMisidentified) {
  const auto db = test::inflightDatabase();
  const test::InflightSimulator sim(*db);
  int with_rule = 0, without = 0, lost = 0;
  for (uint64_t seed = 1; seed <= 200; ++seed) {
    const test::InflightFrame f = sim.frame(seed, 40);
    const Outcome on = solveFrame(f, *db, true), off = solveFrame(f, *db, false);
    const bool good_on = on.solved && on.error_arcsec < kWrongArcsec;
    const bool good_off = off.solved && off.error_arcsec < kWrongArcsec;
    with_rule += good_on, without += good_off;
    lost += good_on && !good_off;
  }
  std::printf("200 frames with 40 hits: %d solved right with the rule, %d without (%d lost)\n",
              with_rule, without, lost);
  EXPECT_GT(lost, 0);
  EXPECT_GT(with_rule, without);
}

}  // namespace
}  // namespace st
