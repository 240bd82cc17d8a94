// Navigator (issue 8): pipeline + MEKF closed loop on simulated runs made in memory with the
// SIM helper's scenario API (SkySimulator: renderer, detector noise, gyro).
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <sstream>
#include <string>

#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "fusion/consistency.hpp"
#include "navigation/navigator.hpp"
#include "navigation/tracker_config.hpp"
#include "sensors/sim/scenario.hpp"
#include "sensors/sim/sim_observations.hpp"

namespace st {
namespace {

/// A small, fast scenario: 256 x 256 px, 20 deg FOV (281 arcsec/px), 12-bit, gain 8 e/ADU.
std::string scenarioIni(const std::string& motion, const std::string& faults, double duration_s,
                        int seed) {
  return "[scenario]\nduration_s = " + std::to_string(duration_s) +
         "\nframe_rate_hz = 10\nstart_time = 2025-03-20T00:00:00\nseed = " +
         std::to_string(seed) +
         "\nmag_limit = 6.5\n"
         "[camera]\nresolution = [256 256]\nfov_deg = 20\n"
         "[sensor]\naperture_diameter_mm = 25\nexposure_s = 0.1\npsf_sigma_px = 1.0\n"
         "read_noise_e = 8\nfull_well_e = 30000\ngain_e_per_adu = 8\nbit_depth = 12\n"
         "bias_adu = 20\n"
         "[motion]\n" +
         motion +
         "\n[gyro]\nrate_hz = 100\narw_deg_rt_h = 0.15\nrrw_deg_h_rt_h = 0.5\nbias_deg_h = 0\n"
         "initial_bias_deg_h = 3 -2 1\n[faults]\n" +
         faults + "\n";
}

Scenario makeScenario(const std::string& ini) {
  mrpt::config::CConfigFileMemory cfg(ini);
  return Scenario::fromConfig(cfg, "test scenario");
}

NavigatorOptions navOptions(const Scenario& sc) {
  NavigatorOptions o;
  o.pipeline.tracker.exposure_s = sc.sensor.exposure_s;
  o.pipeline.tracker.detect.gain_e_per_adu = sc.sensor.gain();
  o.pipeline.tracker.detect.read_noise_adu = sc.sensor.read_noise_e / sc.sensor.gain();
  // The gyro datasheet numbers of the scenario; bias prior covering the 3 deg/h turn-on bias.
  o.fusion.filter = MekfOptions::fromDatasheet(0.15, 0.5, 5.0);
  return o;
}

struct RunResult {
  std::vector<NavStep> steps;
  std::vector<std::string> warnings;
  int frames_with_fix = 0;
  int misidentified = 0;
  int matched_total = 0;
  int reinits = 0;
  int displaced = 0;  ///< right id, centroid > 1 px from the true image (blends)
};

/// Plays a scenario through the navigator in timestamp order (GYRO, CAMERA, GROUND_TRUTH),
/// checking every matched star against the renderer's truth (id and pixel).
RunResult runScenario(const Scenario& sc, const StarDatabase& db, const NavigatorOptions& o,
                      int frames, const std::function<bool(double t)>& gyro_kept = {}) {
  SkySimulator sim(sc, sc.seed);
  Navigator nav(db, sc.camera, o);
  std::map<int64_t, std::vector<TrueStar>> truth_stars;  // by timestamp ticks
  RunResult r;
  nav.setStepCallback([&](const NavStep& s, const std::vector<CObservationStarTracker::Ptr>& fixes) {
    if (fixes.empty() || !fixes[0]->hasAttitude()) return;
    const CObservationStarTracker::Ptr& obs = fixes[0];
    ++r.frames_with_fix;
    const auto& truth = truth_stars[s.stamp.time_since_epoch().count()];
    for (const MatchedStar& m : obs->stars) {
      ++r.matched_total;
      const auto it = std::find_if(truth.begin(), truth.end(),
                                   [&](const TrueStar& ts) { return ts.id == m.catalog_id; });
      // A star's centroid is within a few pixels of its true image (blend-free windows);
      // 3 px is > 20 sigma of any centroid here and far below the 281 arcsec/px to a neighbour.
      // Misidentified: the catalog id is not in the image, or the centroid lies closer to
      // another star's true image than to this one's.
      bool wrong = it == truth.end();
      if (!wrong) {
        const double d = (it->px - m.px).norm();
        if (d > 1.0) ++r.displaced;
        // (A companion within 3 px is an unresolved double, merged in the database.)
        for (const TrueStar& o : truth) {
          if (o.id != m.catalog_id && (o.px - m.px).norm() < d && (o.px - it->px).norm() > 3.0)
            wrong = true;
        }
      }
      if (wrong) ++r.misidentified;
    }
  });
  GyroSample g;
  bool have_g = sim.nextGyro(g);
  for (int k = 0; k < frames; ++k) {
    const SimFrame f = sim.frame(k);
    while (have_g && g.t <= f.t) {
      if (!gyro_kept || gyro_kept(g.t)) nav.push(makeGyroObservation(g.rate, sc.timestamp(g.t)));
      have_g = sim.nextGyro(g);
    }
    const auto stamp = sc.timestamp(f.t);
    truth_stars[stamp.time_since_epoch().count()] = f.truth;
    if (!f.dropped) nav.push(makeCameraObservation(f.image, sc.camera, stamp));
    nav.push(makeTruthObservation(f.q_ib, f.truth, stamp));
  }
  nav.flush();
  r.steps = nav.steps();
  r.warnings = nav.warnings();
  r.reinits = nav.reinitializations();
  return r;
}

const StarDatabase& databaseFor(const Scenario& sc) {
  static std::map<std::string, std::unique_ptr<StarDatabase>> cache;
  const std::string key = sc.camera.describe();
  auto& p = cache[key];
  if (!p) {
    DatabaseSource src;
    src.mag_limit = 6.5;
    p = std::make_unique<StarDatabase>(*makeDatabase(src, sc.camera, sc.epochJyear()));
  }
  return *p;
}

/// Fraction of NEES values (3 dof) below the chi-square quantile p.
double fractionBelow(const std::vector<double>& nees, double p) {
  const double q = chiSquareQuantile(p, 3.0);
  return double(std::count_if(nees.begin(), nees.end(), [&](double v) { return v <= q; })) /
         double(nees.size());
}

// ---- the issue 7/8 acceptance run ----------------------------------------------------------

TEST(NavigatorSlow, ThreeThousandFramesSlewingTracksConsistently) {
  // Slews up to 3 deg/s: a base rate plus slow sinusoids (|w| <= 2.9 deg/s).
  const Scenario sc = makeScenario(
      scenarioIni("type = jitter\nra_deg = 40\ndec_deg = 20\nbase_rate_deg_s = 0 1.5 0\n"
                  "amplitude_deg_s = 1.0 1.2 0.3\nfrequency_hz = 0.011 0.007 0.02",
                  "", 300.0, 11));
  ASSERT_EQ(sc.frameCount(), 3000);
  const RunResult r = runScenario(sc, databaseFor(sc), navOptions(sc), 3000);
  ASSERT_EQ(r.steps.size(), 3000u);

  EXPECT_EQ(r.misidentified, 0) << "of " << r.matched_total << " matched stars";
  int lis_after_first = 0, failed = 0;
  std::vector<double> nees;
  double max_err = 0;
  for (std::size_t k = 0; k < r.steps.size(); ++k) {
    const NavStep& s = r.steps[k];
    ASSERT_TRUE(s.has_frame);
    if (k > 0 && s.mode == StarTrackerMode::kLostInSpace) ++lis_after_first;
    if (s.mode == StarTrackerMode::kFailed) ++failed;
    ASSERT_TRUE(s.has_truth);
    if (k >= 10) {  // after the first second (bias transient)
      nees.push_back(s.nees);
      max_err = std::max(max_err, s.error.total);
    }
  }
  EXPECT_EQ(r.steps[0].mode, StarTrackerMode::kLostInSpace);
  EXPECT_EQ(lis_after_first, 0);
  EXPECT_EQ(r.reinits, 0);
  EXPECT_LE(failed, 10) << "frames without a fix (0.3 %)";
  const double f50 = fractionBelow(nees, 0.5), f95 = fractionBelow(nees, 0.95);
  RecordProperty("max_err_arcsec", std::to_string(rad2arcsec(max_err)));
  std::printf("3000 frames: f50 %.3f f95 %.3f, max error %.1f arcsec, %d stars matched, %d "
              "displaced > 1 px, %d failed\n",
              f50, f95, rad2arcsec(max_err), r.matched_total, r.displaced, failed);
}


// Per-frame consistency of the attitude error with the reported covariance over the same
// 3000-frame run: the per-frame NEES of the filter against truth has the chi-square(3)
// distribution. Was DISABLED while the pipeline's fix covariances were optimistic for streaked
// stars and pessimistic at rest; enabled after the detector's noise model (grouped-data
// background, background-estimate variance, streak windows centred on the streak) and the
// tracking refinement with full centroid covariances made them consistent.
TEST(NavigatorSlow, ThreeThousandFramesNeesCalibration) {
  const Scenario sc = makeScenario(
      scenarioIni("type = jitter\nra_deg = 40\ndec_deg = 20\nbase_rate_deg_s = 0 1.5 0\n"
                  "amplitude_deg_s = 1.0 1.2 0.3\nfrequency_hz = 0.011 0.007 0.02",
                  "", 300.0, 11));
  const RunResult r = runScenario(sc, databaseFor(sc), navOptions(sc), 3000);
  std::vector<double> nees;
  for (std::size_t k = 10; k < r.steps.size(); ++k) nees.push_back(r.steps[k].nees);
  // Consistency of the per-frame error with the reported covariance (NEES, 3 dof): the
  // fraction of frames below the chi-square(3) quantile p must be p. The errors of successive
  // frames are correlated through the filter (a fix every frame, ~a few frames of memory), so
  // count an effective N/10 = 300 independent samples: the binomial standard deviation at
  // p = 0.5 is sqrt(0.25/300) = 0.029; allow 3 of them. At p = 0.95 it is 0.0126 -> 0.04.
  const double f50 = fractionBelow(nees, 0.5), f95 = fractionBelow(nees, 0.95);
  std::cout << "[ info ] NEES fraction below the chi2(3) median " << f50 << ", below the 95 % "
            << "quantile " << f95 << "\n";
  EXPECT_NEAR(f50, 0.5, 0.087);
  EXPECT_NEAR(f95, 0.95, 0.04);
  // Teeth: the same errors against a covariance 4x too small (or too large) fail the test.
  std::vector<double> over(nees), under(nees);
  for (double& v : over) v *= 4.0;
  for (double& v : under) v /= 4.0;
  EXPECT_GT(std::abs(fractionBelow(over, 0.5) - 0.5), 0.087);
  EXPECT_GT(std::abs(fractionBelow(under, 0.5) - 0.5), 0.087);
}

// ---- star-tracker outage --------------------------------------------------------------

TEST(Navigator, ThirtySecondOutageCoastsAndResumesTracking) {
  const Scenario sc = makeScenario(
      scenarioIni("type = slew\nra_deg = 120\ndec_deg = -30\nrate_deg_s = 0.5 1.0 0",
                  "dropout_s = 20 50", 60.0, 5));
  const RunResult r = runScenario(sc, databaseFor(sc), navOptions(sc), sc.frameCount());
  ASSERT_EQ(r.steps.size(), 600u);
  double prev_sigma = 0;
  int lis = 0;
  bool resumed = false;
  for (const NavStep& s : r.steps) {
    if (s.has_frame && s.mode == StarTrackerMode::kLostInSpace) ++lis;
    ASSERT_TRUE(s.initialized);
    const bool outage = s.t >= 20.0 - 1e-6 && s.t < 50.0 - 1e-6;
    EXPECT_EQ(s.has_frame, !outage) << s.t;
    if (outage) {
      // Covariance grows monotonically while coasting; truth inside 3 sigma on every axis.
      const double sigma = s.sigma_att.norm();
      EXPECT_GT(sigma, prev_sigma) << s.t;
      prev_sigma = sigma;
      for (int i = 0; i < 3; ++i)
        EXPECT_LE(std::abs(s.error.rotvec_body[i]), 3.0 * s.sigma_att[i]) << s.t << " axis " << i;
    } else if (s.t >= 50.0 - 1e-6 && !resumed) {
      resumed = true;
      EXPECT_EQ(s.mode, StarTrackerMode::kTracking) << "first frame after the outage";
      EXPECT_EQ(s.use, FixUse::kAccepted);
    } else {
      prev_sigma = 0;
    }
  }
  EXPECT_TRUE(resumed);
  EXPECT_EQ(lis, 1) << "lost-in-space only for the first frame";
  // The 30 s coast grows the 1-sigma from ~arcsec to tens of arcsec (ARW 0.15 deg/rt h over
  // 30 s alone is 49 arcsec per axis).
  const NavStep& last_coast = r.steps[499];
  EXPECT_GT(rad2arcsec(last_coast.sigma_att.minCoeff()), 30.0);
  EXPECT_EQ(r.misidentified, 0);
}

// ---- robustness: out-of-order, duplicates, gyro gap -------------------------------------

TEST(Navigator, OutOfOrderDuplicateAndGapGiveWarningsNotCrashes) {
  const Scenario sc = makeScenario(
      scenarioIni("type = slew\nra_deg = 200\ndec_deg = 45\nrate_deg_s = 0 1 0", "", 6.0, 7));
  const StarDatabase& db = databaseFor(sc);
  SkySimulator sim(sc, sc.seed);
  Navigator nav(db, sc.camera, navOptions(sc));
  std::vector<mrpt::obs::CObservation::Ptr> seq;
  GyroSample g;
  bool have_g = sim.nextGyro(g);
  for (int k = 0; k < sc.frameCount(); ++k) {
    const SimFrame f = sim.frame(k);
    while (have_g && g.t <= f.t) {
      // A gyro gap of 1 s (samples with 2 < t < 3 lost).
      if (!(g.t > 2.0 && g.t < 3.0)) seq.push_back(makeGyroObservation(g.rate, sc.timestamp(g.t)));
      have_g = sim.nextGyro(g);
    }
    seq.push_back(makeCameraObservation(f.image, sc.camera, sc.timestamp(f.t)));
    seq.push_back(makeTruthObservation(f.q_ib, f.truth, sc.timestamp(f.t)));
  }
  // Swap two gyro samples inside the reorder window (silently sorted), duplicate one
  // observation, and move one gyro sample far later (out of order beyond the window).
  std::swap(seq[50], seq[51]);
  const auto dup = seq[199];
  seq.insert(seq.begin() + 200, dup);
  auto late = seq[100];
  seq.erase(seq.begin() + 100);
  seq.insert(seq.begin() + 400, late);
  const double late_t = nav.secondsFromStart(late->timestamp);  // t0 not set yet: 0
  (void)late_t;
  for (const auto& o : seq) nav.push(o);
  nav.push(nullptr);  // ignored
  nav.flush();

  const auto& w = nav.warnings();
  auto has = [&](const std::string& what) {
    return std::any_of(w.begin(), w.end(),
                       [&](const std::string& m) { return m.find(what) != std::string::npos; });
  };
  EXPECT_TRUE(has("duplicate")) << ::testing::PrintToString(w);
  EXPECT_TRUE(has("out-of-order")) << ::testing::PrintToString(w);
  EXPECT_TRUE(has("gyro gap")) << ::testing::PrintToString(w);
  // Every warning names its timestamp.
  for (const auto& m : w) EXPECT_NE(m.find("t = "), std::string::npos) << m;
  // The swap inside the window is not a warning: exactly one out-of-order message.
  EXPECT_EQ(std::count_if(w.begin(), w.end(),
                          [](const std::string& m) {
                            return m.find("out-of-order") != std::string::npos;
                          }),
            1);
  // Tracking carried on through all of it, with the truth inside 3 sigma.
  ASSERT_EQ(nav.steps().size(), std::size_t(sc.frameCount()));
  for (std::size_t k = 1; k < nav.steps().size(); ++k) {
    const NavStep& s = nav.steps()[k];
    EXPECT_EQ(s.mode, StarTrackerMode::kTracking) << s.t << " " << s.reason;
    EXPECT_LT(s.nees, chiSquareQuantile(0.9999, 3.0)) << s.t;
  }
}

// ---- disagreement -> re-initialisation ----------------------------------------------------

TEST(Navigator, ReinitialisesFromLostInSpaceWhenTheSkyJumps) {
  // The camera's frames come from a hold at one pointing for 3 s, then from another pointing
  // 10 deg away, while the gyro keeps saying "hold": filter and sensor disagree.
  const Scenario a = makeScenario(
      scenarioIni("type = hold\nra_deg = 300\ndec_deg = 10", "", 8.0, 9));
  const Scenario b = makeScenario(
      scenarioIni("type = hold\nra_deg = 310\ndec_deg = 10", "", 8.0, 9));
  const StarDatabase& db = databaseFor(a);
  SkySimulator sa(a, 9), sb(b, 9);
  Navigator nav(db, a.camera, navOptions(a));
  GyroSample g;
  bool have_g = sa.nextGyro(g);
  for (int k = 0; k < a.frameCount(); ++k) {
    const bool jumped = k >= 30;
    const SimFrame f = jumped ? sb.frame(k) : sa.frame(k);
    while (have_g && g.t <= f.t) {
      nav.push(makeGyroObservation(g.rate, a.timestamp(g.t)));
      have_g = sa.nextGyro(g);
    }
    nav.push(makeCameraObservation(f.image, a.camera, a.timestamp(f.t)));
    nav.push(makeTruthObservation(f.q_ib, f.truth, a.timestamp(f.t)));
  }
  nav.flush();
  EXPECT_EQ(nav.reinitializations(), 1);
  // At the end the filter follows the new pointing again, consistently.
  const NavStep& last = nav.steps().back();
  EXPECT_EQ(last.mode, StarTrackerMode::kTracking);
  EXPECT_LT(last.nees, chiSquareQuantile(0.9999, 3.0));
  EXPECT_LT(rad2arcsec(last.error.cross_boresight), 60.0);
}

// ---- no filter (a run without gyro, issue 21 item 3) ------------------------------------

TEST(Navigator, WithoutFilterEveryFrameIsLostInSpaceAndItsFixTheOutput) {
  const Scenario sc = makeScenario(
      scenarioIni("type = slew\nra_deg = 200\ndec_deg = 45\nrate_deg_s = 0 1 0", "", 2.0, 7));
  NavigatorOptions o = navOptions(sc);
  o.fusion.filter_enabled = false;
  const RunResult r = runScenario(sc, databaseFor(sc), o, sc.frameCount());
  ASSERT_EQ(r.steps.size(), std::size_t(sc.frameCount()));
  int fixes = 0;
  for (const NavStep& s : r.steps) {
    ASSERT_TRUE(s.has_frame);
    EXPECT_FALSE(s.initialized) << s.t;
    EXPECT_EQ(s.mode, s.fix ? StarTrackerMode::kLostInSpace : StarTrackerMode::kFailed) << s.t;
    EXPECT_EQ(s.use, s.fix ? FixUse::kUnfiltered : FixUse::kNoFix) << s.t;
    if (!s.fix) continue;
    ++fixes;
    ASSERT_TRUE(s.has_truth);
    // A fix's own covariance holds its error (281 arcsec/px: a few arcsec to tens).
    EXPECT_LT(s.fix_nees, chiSquareQuantile(0.9999, 3.0)) << s.t;
  }
  EXPECT_GE(fixes, sc.frameCount() - 1);
  EXPECT_EQ(r.reinits, 0);
  EXPECT_EQ(r.misidentified, 0);
}

// A gyro that stops on a turning body: coasting on the last rate would leave the filter's
// covariance behind (issue 21: the tour's jitter with the gyro stopping at 60 s ended 8 deg
// off, NEES 1e5). Past max_gyro_coast_s the filter is suspended (no state reported), frames are
// solved lost-in-space and their fixes pass unfiltered; when the gyro returns, a lost-in-space
// fix re-initialises the attitude and tracking resumes, consistent again.
TEST(Navigator, GyroStoppingOnATurningBodySuspendsTheFilterUntilItReturns) {
  const Scenario sc = makeScenario(scenarioIni(
      "type = jitter\nra_deg = 100\ndec_deg = 10\nbase_rate_deg_s = 0 0.5 0\n"
      "amplitude_deg_s = 0.3 0.2 0.5\nfrequency_hz = 0.05 0.08 0.03",
      "", 16.0, 7));
  const double stop = 5.0, back = 11.0;
  const NavigatorOptions o = navOptions(sc);
  const RunResult r = runScenario(sc, databaseFor(sc), o, sc.frameCount(),
                                  [&](double t) { return t < stop || t >= back; });
  ASSERT_EQ(r.steps.size(), std::size_t(sc.frameCount()));
  auto has = [&](const std::string& what) {
    return std::any_of(r.warnings.begin(), r.warnings.end(),
                       [&](const std::string& m) { return m.find(what) != std::string::npos; });
  };
  EXPECT_TRUE(has("gyro lost")) << ::testing::PrintToString(r.warnings);
  EXPECT_TRUE(has("gyro samples again")) << ::testing::PrintToString(r.warnings);
  EXPECT_EQ(r.reinits, 1);
  int suspended = 0;
  std::vector<double> nees_after;
  for (const NavStep& s : r.steps) {
    const double silent = s.t - stop;
    if (s.t < stop || s.t >= back + 1.0) {
      EXPECT_TRUE(s.initialized) << s.t;
      if (s.t >= back + 1.0) nees_after.push_back(s.nees);
      continue;
    }
    if (silent > o.fusion.max_gyro_coast_s + 0.15 && s.t < back) {
      // Suspended: no filter state, every frame lost-in-space, the fix unfiltered and right.
      ++suspended;
      EXPECT_FALSE(s.initialized) << s.t;
      if (!s.fix) continue;
      EXPECT_EQ(s.mode, StarTrackerMode::kLostInSpace) << s.t;
      EXPECT_EQ(s.use, FixUse::kUnfiltered) << s.t;
      EXPECT_LT(s.fix_nees, chiSquareQuantile(0.9999, 3.0)) << s.t;
    }
  }
  EXPECT_GE(suspended, 40);
  ASSERT_GE(nees_after.size(), 30u);
  for (double v : nees_after) EXPECT_LT(v, chiSquareQuantile(0.9999, 3.0));
  EXPECT_EQ(r.steps.back().mode, StarTrackerMode::kTracking);
  EXPECT_EQ(r.misidentified, 0);
}

// ---- configuration ------------------------------------------------------------------------

TEST(NavigatorConfig, ReadsTrackerIniAndNamesBadKeys) {
  mrpt::config::CConfigFileMemory good(
      "[filter]\narw_deg_rt_h = 0.3\nupdate = stars\n[pipeline]\ngain_e_per_adu = 8\n"
      "track_solver = svd\n[navigator]\nreinit_after_rejections = 5\n[database]\nmag_limit = 6\n");
  const TrackerConfig c = TrackerConfig::fromConfig(good, "t.ini");
  EXPECT_NEAR(c.nav.fusion.filter.arw_rad_rt_s, deg2rad(0.3) / 60.0, 1e-15);
  EXPECT_EQ(c.nav.fusion.update, FusionOptions::Update::kStarVectors);
  EXPECT_EQ(c.nav.pipeline.tracker.detect.gain_e_per_adu, 8.0);
  EXPECT_EQ(c.nav.pipeline.tracker.solver, "svd");
  EXPECT_EQ(c.nav.fusion.reinit_after_rejections, 5);
  EXPECT_EQ(c.database.mag_limit, 6.0);
  EXPECT_FALSE(c.camera.has_value());

  auto message = [](const std::string& ini) -> std::string {
    try {
      mrpt::config::CConfigFileMemory cfg(ini);
      TrackerConfig::fromConfig(cfg, "bad.ini");
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(message("[filter]\narw_deg_rt_h = fast\n").find("[filter] arw_deg_rt_h"),
            std::string::npos);
  EXPECT_NE(message("[pipeline]\ngain_e_per_adu_typo = 3\n").find("gain_e_per_adu_typo"),
            std::string::npos);
  EXPECT_NE(message("[pipeline]\ntrack_solver = nonsense\n").find("bad.ini: [pipeline] key 'track_solver'"),
            std::string::npos);
  // An old key name is refused naming its new name, never silently taken or ignored.
  EXPECT_NE(message("[pipeline]\ngate_sigma = 3\n").find("key 'gate_sigma': renamed to 'track_gate_sigma'"),
            std::string::npos);
  EXPECT_NE(message("[filter]\nupdate = both\n").find("update"), std::string::npos);
  EXPECT_NE(message("[navigator]\nreinit_after_rejections = 0\n").find("reinit_after"),
            std::string::npos);
  EXPECT_NE(message("[database]\naberration = maybe\n").find("aberration"), std::string::npos);
}

// Issue 36 item 5: the fusion keys bound directly to the loop's options, units converted at
// the edge. What a file says is what the filter gets, the printed configuration says it in the
// file's units with the fewest digits, and reads back to the very same options.
TEST(NavigatorConfig, FusionKeysConvertAtTheEdgeAndReadBackExactly) {
  mrpt::config::CConfigFileMemory cfg(
      "[filter]\narw_deg_rt_h = 0.123\nrrw_deg_h_rt_h = 0.77\nbias_sigma_deg_h = 3.3\n"
      "model = gyroless\nrate_sigma_deg_s = 1.7\n"
      "[navigator]\ngyro_max_accel_deg_s2 = 7.5\ngyro_mount_ypr_deg = 10 -20 30\n");
  const TrackerIniKeys k = readTrackerIni(IniReader{cfg, "t.ini"});
  const FusionOptions& f = k.nav.fusion;
  EXPECT_EQ(f.filter.arw_rad_rt_s, gyro_units::arwToFilter(0.123));
  EXPECT_EQ(f.filter.rrw_rad_s_rt_s, gyro_units::rrwToFilter(0.77));
  EXPECT_EQ(f.filter.initial_bias_sigma_rad_s, gyro_units::biasToFilter(3.3));
  EXPECT_EQ(f.filter.initial_rate_sigma_rad_s, deg2rad(1.7));
  EXPECT_EQ(f.filter.model, MekfOptions::Model::kGyroless);
  EXPECT_EQ(f.gyro_health.max_angular_accel_rad_s2, deg2rad(7.5));
  EXPECT_NEAR((f.R_body_gyro * Vec3::UnitX()).z(), -std::sin(deg2rad(-20)), 1e-12);
  const std::string printed = printTrackerIni(k);
  for (const char* line : {"arw_deg_rt_h = 0.123\n", "rrw_deg_h_rt_h = 0.77\n",
                           "bias_sigma_deg_h = 3.3\n", "rate_sigma_deg_s = 1.7\n",
                           "model = gyroless\n", "gyro_max_accel_deg_s2 = 7.5\n"})
    EXPECT_NE(printed.find(line), std::string::npos) << line << printed;
  mrpt::config::CConfigFileMemory again(printed);
  const TrackerIniKeys k2 = readTrackerIni(IniReader{again, "printed.ini"});
  const FusionOptions& g = k2.nav.fusion;
  EXPECT_EQ(g.filter.arw_rad_rt_s, f.filter.arw_rad_rt_s);
  EXPECT_EQ(g.filter.rrw_rad_s_rt_s, f.filter.rrw_rad_s_rt_s);
  EXPECT_EQ(g.filter.initial_bias_sigma_rad_s, f.filter.initial_bias_sigma_rad_s);
  EXPECT_EQ(g.filter.initial_rate_sigma_rad_s, f.filter.initial_rate_sigma_rad_s);
  EXPECT_EQ(g.gyro_health.max_angular_accel_rad_s2, f.gyro_health.max_angular_accel_rad_s2);
  EXPECT_LT((g.R_body_gyro - f.R_body_gyro).norm(), 1e-12);
  EXPECT_EQ(printTrackerIni(k2), printed);
  // A range is stated and checked in the key's unit, not the filter's.
  mrpt::config::CConfigFileMemory wild("[filter]\narw_deg_rt_h = 101\n");
  try {
    readTrackerIni(IniReader{wild, "w.ini"});
    ADD_FAILURE() << "arw_deg_rt_h = 101 accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'arw_deg_rt_h' = 101: must be from 0 to 100"),
              std::string::npos)
        << e.what();
  }
}

TEST(NavigatorCsv, OneColumnPerHeaderField) {
  NavStep s;
  s.has_frame = true;
  s.mode = StarTrackerMode::kTracking;
  const auto count = [](const std::string& l) { return std::count(l.begin(), l.end(), ','); };
  EXPECT_EQ(count(navStepCsvHeader()), count(navStepCsvRow(s)));
  s.fix = s.has_truth = s.initialized = true;
  EXPECT_EQ(count(navStepCsvHeader()), count(navStepCsvRow(s)));
}

// Absent is "nan", never a 0 that reads as a perfect estimate: no filter state -> the
// filter's columns; no fix -> the fix's.
TEST(NavigatorCsv, AbsentFilterAndFixColumnsAreNan) {
  const auto field = [](const std::string& row, const std::string& name) {
    std::stringstream h(navStepCsvHeader()), r(row);
    for (std::string hn, rv; std::getline(h, hn, ',') && std::getline(r, rv, ',');)
      if (hn == name) return rv;
    return std::string("<no column>");
  };
  NavStep s;
  s.has_frame = true;
  s.mode = StarTrackerMode::kLostInSpace;
  s.fix = s.has_truth = true;
  s.q_fix = Quat(0.5, 0.5, 0.5, 0.5);
  s.cov_fix = Mat3::Identity() * 1e-10;
  const std::string row = navStepCsvRow(s);
  for (const char* c : {"qw", "bias_x_deg_h", "sigma_x_arcsec", "err_arcsec", "nees",
                        "sigma_roll_arcsec"})
    EXPECT_EQ(field(row, c), "nan") << c;
  EXPECT_EQ(field(row, "fix"), "1");
  EXPECT_EQ(std::stod(field(row, "fix_qw")), 0.5);
  EXPECT_NE(field(row, "fix_sigma_roll_arcsec"), "nan");
  s.fix = false;
  s.initialized = true;
  const std::string row2 = navStepCsvRow(s);
  EXPECT_EQ(field(row2, "fix_qw"), "nan");
  EXPECT_EQ(field(row2, "fix_nees"), "nan");
  EXPECT_NE(field(row2, "qw"), "nan");
}

}  // namespace
}  // namespace st
