// Radiation hits told from stars (issue 34, sensors/detect/radiation_hits.hpp) on simulated
// in-flight frames (rows binned 2x, 8-bit, hits from a particle flux): detection flags the
// bright hits and (almost) no star, ranks the hits after every star, and a tracking window
// refuses a hit in place of its star. Each rule's test is run once with the rule off
// (DetectorOptions::flag_hits = false) and must then fail.
#include <gtest/gtest.h>

#include <cstdio>
#include <cmath>

#include "sensors/detect/star_detector.hpp"
#include "tests/detect/inflight_frame.hpp"

namespace st {
namespace {

// Distance from p to the segment a-b.
double toSegment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 d = b - a;
  const double t = d.squaredNorm() > 0 ? std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0;
  return (p - (a + t * d)).norm();
}

struct Tally {
  int stars = 0, stars_flagged = 0;          // detections on a true star, no hit near
  int bright_hits = 0, bright_hits_flagged = 0;  // on a hit of peak >= kBrightAdu, no star near
  int bright_dots = 0, bright_dots_flagged = 0;  // ... whose track is under half a pixel
  int hits_before_stars = 0;                 // a flagged hit ranked above an unflagged star
};

// [ADU above the background] a hit this bright is one the rule must see: its neighbours
// (charge diffusion 0.3 native px) hold ~10 % of it along x where a star's hold > 100 %.
constexpr double kBrightAdu = 60;

Tally tally(const test::InflightSimulator& sim, int frames, double mean_hits, bool rule) {
  DetectorOptions o;
  o.flag_hits = rule;
  o.pixel_aspect = test::inflightCamera().pixelAspect();  // as solve and the tracker set it
  StarDetector det(o);
  Tally t;
  for (int k = 0; k < frames; ++k) {
    const test::InflightFrame f = sim.frame(1000 + static_cast<uint64_t>(k), mean_hits);
    const DetectionResult r = det.detect(f.image);
    bool seen_hit = false;
    for (const Centroid& c : r.stars) {
      double d_star = 1e9, d_hit = 1e9, len = 0;
      for (const TrueStar& s : f.truth) d_star = std::min(d_star, (c.px - s.px).norm());
      for (const RadiationHit& h : f.hits)
        if (const double d = toSegment(c.px, h.from, h.to); d < d_hit) d_hit = d, len = (h.to - h.from).norm();
      const bool flagged = (c.flags & kRadiationHit) != 0;
      if (flagged) seen_hit = true;
      if (d_star < 1.5 && d_hit > 4) {
        ++t.stars, t.stars_flagged += flagged;
        t.hits_before_stars += seen_hit && !flagged;
      } else if (d_hit < 1.5 && d_star > 4 && c.peak >= kBrightAdu) {
        ++t.bright_hits, t.bright_hits_flagged += flagged;
        if (len < 0.5) ++t.bright_dots, t.bright_dots_flagged += flagged;
      }
    }
  }
  return t;
}

/// The simulator of these tests (one database, one renderer for the whole file).
const test::InflightSimulator& simulator() {
  static const auto db = test::inflightDatabase();
  static const test::InflightSimulator sim(*db);
  return sim;
}

TEST(RadiationHits, BrightHitsAreFlaggedStarsAreNotAndHitsRankLast) {
  const test::InflightSimulator& sim = simulator();
  const Tally t = tally(sim, 40, 60, true);
  std::printf("stars %d (flagged %d), bright hits %d (flagged %d), of them dots %d (flagged %d)\n",
              t.stars, t.stars_flagged, t.bright_hits, t.bright_hits_flagged, t.bright_dots,
              t.bright_dots_flagged);
  ASSERT_GT(t.stars, 400);
  ASSERT_GT(t.bright_hits, 200);
  EXPECT_LE(t.stars_flagged, t.stars / 100);  // at most 1 % of the stars lost to the rule
  // The 3x3 around a peak tells a hit only where some direction is bare: a dot centred on a
  // pixel (the single-pixel ones are already hot pixels), a track across an axis or a
  // diagonal. A dot on a pixel corner (a 2x2 block) or a bent track has light on every side
  // of its peak and passes: measured 56 % of the bright hits flagged here; half at least.
  EXPECT_GE(t.bright_hits_flagged, t.bright_hits / 2);
  EXPECT_EQ(t.hits_before_stars, 0);
  // Teeth: without the rule no hit is flagged.
  const Tally off = tally(sim, 10, 60, false);
  EXPECT_EQ(off.bright_hits_flagged, 0);
  EXPECT_GT(off.bright_hits, 0);
}

TEST(RadiationHits, FrameWithoutHitsHasItsPsfMeasuredPerAxis) {
  const test::InflightFrame f = simulator().frame(7, 0);
  const DetectionResult r = detectStars(f.image);
  // Rows binned 2x: the three-pixel width along y is about half the one along x (PSF sigma
  // 1 px native: pixel-integrated ~1.0 px along x, ~0.55 along y).
  EXPECT_GT(r.psf_width_x, 0.8);
  EXPECT_LT(r.psf_width_x, 1.3);
  EXPECT_GT(r.psf_width_y, 0.4);
  EXPECT_LT(r.psf_width_y, 0.75);
  EXPECT_EQ(r.hits, 0);
}

TEST(RadiationHits, TrackingWindowRefusesAHitInPlaceOfItsStar) {
  const test::InflightSimulator& sim = simulator();
  const test::InflightFrame f = sim.frame(11, 0);
  // The full frame first: the detector learns the frame's PSF.
  StarDetector det(DetectorOptions{});
  ASSERT_GT(det.detect(f.image).psf_width_x, 0);
  // A dot hit of ~150 ADU where a star is predicted but none is.
  cv::Mat e(f.image.size(), CV_64F, cv::Scalar(0));
  RadiationHit h;
  h.from = h.to = Vec2(200.3, 150.1);
  h.electrons = 1500;
  renderRadiationHit(e, sim.sensor(), h);
  cv::Mat with_hit;
  cv::Mat adu;
  e.convertTo(adu, CV_8U, 1.0 / sim.sensor().gain());
  cv::add(f.image, adu, with_hit);
  PredictedStar p;
  p.px = Vec2(201, 150);
  p.cov_px = Mat2::Identity() * 4;
  std::vector<WindowResult> w;
  det.centroidWindows(with_hit, {p}, w);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_FALSE(w[0].centroid) << "a hit was taken for the star";
  EXPECT_NE(w[0].reason.find("radiation hit"), std::string::npos) << w[0].reason;
  // Teeth: with the rule off the window takes the hit.
  DetectorOptions off;
  off.flag_hits = false;
  StarDetector det_off(off);
  det_off.detect(f.image);
  det_off.centroidWindows(with_hit, {p}, w);
  EXPECT_TRUE(w[0].centroid);
}

}  // namespace
}  // namespace st
