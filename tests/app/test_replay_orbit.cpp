// An orbiting star tracker (issue 16 item 3), end to end through the commands a user runs:
// `simulate` renders rawlogs/orbit_leo.ini (600 km polar orbit, 7.56 km/s: every star moved up
// to 5.2" towards the apex, the boresight along the orbit normal where all of it falls across
// the boresight) with VELOCITY samples; `replay` corrects every fix for them.
//  - corrected (rawlogs/tracker.ini): the filter's NEES fractions in their chi-square band
//    (live_cli_util.hpp: 3 binomial sigma of N/10 effective samples, teeth: 4x-optimistic
//    covariance fails), cross-boresight error RMS below 2" (1.0" measured);
//  - uncorrected (the same ini with [navigator] velocity_aberration = false): the systematic
//    error shows, cross-boresight RMS above 4" (5.4" measured, the 5.2" bias in quadrature
//    with the noise) and the NEES band fails.
#include <gtest/gtest.h>

#include <regex>
#include <string>
#include <vector>

#include "tests/app/live_cli_util.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

double grab(const std::string& out, const std::string& pattern) {
  std::smatch m;
  if (!std::regex_search(out, m, std::regex(pattern))) return -1;
  return std::stod(m[1]);
}

struct OrbitRun {
  std::string out;
  double cross_rms = -1;
  bool nees_in_band = false;
  std::string nees_report;
};

OrbitRun replay(const std::string& rawlog, const std::string& ini, const std::string& csv) {
  OrbitRun r;
  EXPECT_EQ(test::runCommand(test::startrackerExe() + " replay -q " + rawlog + " --config " + ini +
                                 " --csv " + csv,
                             &r.out),
            0)
      << r.out;
  r.cross_rms = grab(r.out, R"(cross-boresight\s+RMS\s+([0-9.]+))");
  const std::vector<double> nees = test::csvColumn(csv, "nees", "has_truth", 10);
  EXPECT_GE(nees.size(), 130u) << r.out;
  r.nees_report = test::neesFractionsInBand(nees, &r.nees_in_band);
  return r;
}

TEST(ReplayOrbit, VelocityAberrationIsCorrectedAndItsAbsenceShows) {
  const std::string dir = test::makeTempDir("replay_orbit");
  const std::string rawlogs = test::repoDir() + "/rawlogs/";
  const std::string rawlog = dir + "/orbit.rawlog";
  std::string out;
  ASSERT_EQ(test::runCommand(test::startrackerExe() + " simulate " + rawlogs +
                                 "orbit_leo.ini --frames 150 -o " + rawlog,
                             &out),
            0)
      << out;
  EXPECT_NE(out.find("7.558 km/s (aberration up to 5.20 arcsec), 31 velocity samples"),
            std::string::npos)
      << out;

  const OrbitRun fixed = replay(rawlog, rawlogs + "tracker.ini", dir + "/c.csv");
  std::printf("corrected: cross-boresight RMS %.2f\", %s\n", fixed.cross_rms,
              fixed.nees_report.c_str());
  EXPECT_EQ(grab(fixed.out, R"(, (\d+) misidentified)"), 0) << fixed.out;
  EXPECT_GT(fixed.cross_rms, 0) << fixed.out;
  EXPECT_LT(fixed.cross_rms, 2.0) << fixed.out;
  EXPECT_TRUE(fixed.nees_in_band) << fixed.nees_report << "\n" << fixed.out;

  const OrbitRun raw = replay(rawlog, rawlogs + "orbit_uncorrected.ini", dir + "/u.csv");
  std::printf("uncorrected: cross-boresight RMS %.2f\", %s\n", raw.cross_rms,
              raw.nees_report.c_str());
  EXPECT_NE(raw.out.find("not used: velocity_aberration is off"), std::string::npos) << raw.out;
  EXPECT_GT(raw.cross_rms, 4.0) << raw.out;
  EXPECT_FALSE(raw.nees_in_band) << raw.nees_report;
}

}  // namespace
}  // namespace st
