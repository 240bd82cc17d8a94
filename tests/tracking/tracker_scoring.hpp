// Scoring of StarTracker runs on simulated frames against their truth (identities, NEES
// bands), shared by the tracker tests.
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>
#include <vector>

#include "common/chi_square.hpp"
#include "common/conventions.hpp"
#include "sensors/tracking/frame.hpp"
#include "tests/tracking/tracker_sim.hpp"

namespace st::test::scoring {

using test::FrameSimulator;

inline double chi2Quantile(double dof, double p) { return chiSquareQuantile(p, dof); }

/// Statistics of a run against truth.
struct RunStats {
  std::map<StarTrackerMode, int> modes;
  int misidentified = 0;   // matched star whose claimed identity is not the true star there
  int displaced = 0;       // right identity, centroid far from the true image (see score)
  int matched = 0;
  std::vector<double> nees;
  double max_error_arcsec = 0;
  std::set<uint32_t> ids_seen;
};

/// Checks one output against the frame's truth (q_ib_true in the body frame).
inline void score(const FrameResult& o, const FrameSimulator::Frame& f,
           const Quat& q_ib_true, RunStats& s) {
  ++s.modes[o.mode];
  if (!o.hasAttitude()) return;
  // Blur of the frame [px]: the centroid of a streak may sit a fraction of it off.
  const double blur_px = f.rate_body.norm() * test::simSensor().exposure_s /
                         test::simCamera().pixelScale();
  for (const MatchedStar& m : o.stars) {
    ++s.matched;
    s.ids_seen.insert(m.catalog_id);
    // Misidentified unless the true star nearest to the centroid is the claimed one.
    const TrueStar* nearest = nullptr;
    for (const TrueStar& t : f.stars) {
      if (!nearest || (t.px - m.px).norm() < (nearest->px - m.px).norm()) nearest = &t;
    }
    if (!nearest || nearest->id != m.catalog_id) {
      ++s.misidentified;
    } else if ((nearest->px - m.px).norm() > 1.5 + 0.25 * blur_px) {
      // Displaced: 1.5 px is ~10 sigma of the centroid error of the faintest round stars
      // (SNR ~ 10), plus a quarter of the streak for blurred ones. A faint streak (SNR ~ 5)
      // has ~1.5 px of CoG error along it, so a rare one lands here with the right identity.
      ++s.displaced;
    }
  }
  s.nees.push_back(attitudeNees(o.q_ib, o.cov_body, q_ib_true));
  s.max_error_arcsec =
      std::max(s.max_error_arcsec, rad2arcsec(attitudeError(o.q_ib, q_ib_true).total));
}

/// Identities all right, and displaced centroids rare (<= 0.5 % of the matches).
inline void expectRightStars(const RunStats& s) {
  EXPECT_EQ(s.misidentified, 0) << "of " << s.matched;
  EXPECT_LE(s.displaced, s.matched / 200) << "of " << s.matched << " displaced";
}

inline double meanNees(const RunStats& s) {
  double sum = 0;
  for (double v : s.nees) sum += v;
  return s.nees.empty() ? NAN : sum / double(s.nees.size());
}

/// Mean NEES of n fixes below the upper 99.5% point of chi2(3n)/n: the reported covariance
/// is not optimistic (what a filter fed with these fixes needs).
inline void expectNotOptimistic(const RunStats& s) {
  ASSERT_FALSE(s.nees.empty());
  const double n = double(s.nees.size());
  EXPECT_LT(meanNees(s), chi2Quantile(3 * n, 0.995) / n) << "covariance too optimistic";
}

/// Mean NEES of n fixes inside the two-sided 99% band of chi2(3n)/n.
inline void expectConsistent(const RunStats& s) {
  ASSERT_FALSE(s.nees.empty());
  const double n = double(s.nees.size());
  const double lo = chi2Quantile(3 * n, 0.005) / n, hi = chi2Quantile(3 * n, 0.995) / n;
  EXPECT_GT(meanNees(s), lo) << "covariance too pessimistic";
  EXPECT_LT(meanNees(s), hi) << "covariance too optimistic";
}

inline Quat startAttitude() {
  // Orion: a rich field for a 16 x 12 deg camera.
  return attitudeFromRaDecRoll({deg2rad(84.0), deg2rad(-2.0), deg2rad(25.0)});
}

}  // namespace st::test::scoring
