// Gyroless replay (issue 16 item 1), end to end: rawlogs with no GYRO observation replayed with
// [filter] model = gyroless (rawlogs/gyroless_tracker.ini). The filter's rate state predicts
// every frame after the first, so the tracker tracks from frame 2 on, with no star
// misidentified; the summary and the CSV carry the rate and its error against the truth.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/csv_file.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

namespace fs = std::filesystem;

double grab(const std::string& out, const std::string& pattern) {
  std::smatch m;
  if (!std::regex_search(out, m, std::regex(pattern))) return -1;
  return std::stod(m[1]);
}

using test::readCsvRows;

std::string ini(const std::string& name) { return test::repoDir() + "/rawlogs/" + name; }

// The 60 s sample scenario (jitter, rates up to ~1 deg/s changing all the time, 5 Hz, no
// gyro). Bounds:
//  - tracking from frame 2: every frame after the first is a tracking frame (the filter's
//    prediction, PredictionSource::kExternal), one lost-in-space fix in all;
//  - rate error: the filter's rate against the truth's (central differences of the true
//    attitudes) within the filter's own 1-sigma per axis, RMS over the run: the filter's
//    covariance is the theory of its error. With the sample's rate walk the rate covariance
//    is conservative for this deterministic jitter (rate NEES mean 1.0 measured, 3 for a
//    matched model), so RMS <= sqrt(mean sigma^2) holds with margin but is not loose: it
//    fails for a filter whose rate lags the jitter (rate walk 2e-4: error 10x larger);
//  - attitude NEES: at least 90 % of steps below the chi2(3) 95 % point (0.95 measured).
TEST(ReplayGyroless, SixtySecondJitterTracksFromFrameTwoWithRateAgainstTruth) {
  const std::string dir = test::makeTempDir("replay_gyroless");
  const std::string rawlog = dir + "/gl.rawlog", csv = dir + "/gl.csv";
  std::string out;
  ASSERT_EQ(test::runCommand(test::startrackerExe() + " simulate -q " + ini("gyroless_60s.ini") +
                                 " -o " + rawlog,
                             &out),
            0)
      << out;
  ASSERT_EQ(test::runCommand(test::startrackerExe() + " replay " + rawlog + " --config " +
                                 ini("gyroless_tracker.ini") + " --csv " + csv,
                             &out),
            0)
      << out;
  std::printf("%s\n", out.substr(out.find("frames:")).c_str());
  EXPECT_NE(out.find("gyroless filter ([filter] model = gyroless)"), std::string::npos) << out;
  EXPECT_EQ(grab(out, R"(frames: (\d+))"), 300) << out;
  EXPECT_EQ(grab(out, R"(lost-in-space (\d+))"), 1) << out;
  EXPECT_EQ(grab(out, R"(re-initialisations (\d+))"), 0) << out;
  EXPECT_EQ(grab(out, R"(, (\d+) misidentified)"), 0) << out;
  EXPECT_GE(grab(out, R"(filter NEES: [0-9.]+ below the chi2\(3\) median, ([0-9.]+) below)"), 0.9)
      << out;
  EXPECT_GE(grab(out, R"(filter rate \(gyroless state\) error RMS x ([0-9.]+))"), 0) << out;

  const auto rows = readCsvRows(csv);
  ASSERT_EQ(rows.size(), 300u);
  EXPECT_EQ(rows[0].at("mode"), "lost-in-space");
  int tracking_after_first = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) tracking_after_first += rows[i].at("mode") == "tracking";
  EXPECT_EQ(tracking_after_first, 299);
  double se[3] = {0, 0, 0}, var[3] = {0, 0, 0};
  int n = 0;
  const char* ax = "xyz";
  for (const auto& r : rows) {
    if (r.at("true_rate_x_deg_s") == "nan" || r.at("rate_x_deg_s") == "nan") continue;
    for (int a = 0; a < 3; ++a) {
      const std::string k = std::string("_") + ax[a] + "_deg_s";
      const double e = std::stod(r.at("rate" + k)) - std::stod(r.at("true_rate" + k));
      se[a] += e * e;
      var[a] += std::pow(std::stod(r.at("sigma_rate" + k)), 2);
    }
    ++n;
  }
  ASSERT_GT(n, 290);
  for (int a = 0; a < 3; ++a) {
    const double rms = std::sqrt(se[a] / n), sigma = std::sqrt(var[a] / n);
    std::printf("rate %c: error RMS %.5f deg/s, filter 1-sigma (RMS) %.5f deg/s\n", ax[a], rms,
                sigma);
    EXPECT_LE(rms, sigma) << ax[a];
  }
}

// The 1.2 s slew sample at 2 deg/s, twice the rate prior's 1 sigma: frame 2 tracks with the
// prior's zero rate, so its 7 px streaks are windowed and fitted as points (few stars, a fix
// 19" off for a 3" sigma, measured); the filter takes it, frame 3 fails its consistency
// check, and from frame 4 on the filter's rate (2.00 +- 0.013 deg/s) carries the tracking.
// Asserted: one lost-in-space fix, at most one failed frame, no misidentification, the final
// rate within 3 sigma of the true 2 deg/s about y.
TEST(ReplayGyroless, CameraOnlySlewTracksFromFrameTwo) {
  const std::string dir = test::makeTempDir("replay_gyroless_slew");
  const std::string csv = dir + "/slew.csv";
  std::string out;
  // GYRO samples present in the rawlog are not used by a gyroless filter (one warning).
  ASSERT_EQ(test::runCommand(test::startrackerExe() + " replay " + test::repoDir() +
                                 "/rawlogs/slew_2dps.rawlog --config " +
                                 ini("gyroless_tracker.ini") + " --csv " + csv,
                             &out),
            0)
      << out;
  EXPECT_NE(out.find("not used: the filter model is gyroless"), std::string::npos) << out;
  EXPECT_EQ(grab(out, R"(lost-in-space (\d+))"), 1) << out;
  EXPECT_EQ(grab(out, R"(, (\d+) misidentified)"), 0) << out;
  const auto rows = readCsvRows(csv);
  ASSERT_EQ(rows.size(), 12u);
  EXPECT_EQ(rows[1].at("mode"), "tracking");
  int failed = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) failed += rows[i].at("mode") != "tracking";
  EXPECT_LE(failed, 1);
  const auto& last = rows[10];  // the last row with a true rate (central difference)
  ASSERT_NE(last.at("true_rate_y_deg_s"), "nan");
  const double ry = std::stod(last.at("rate_y_deg_s")), sy = std::stod(last.at("sigma_rate_y_deg_s"));
  EXPECT_NEAR(std::stod(last.at("true_rate_y_deg_s")), 2.0, 1e-3);
  EXPECT_NEAR(ry, 2.0, 3 * sy) << "sigma " << sy;
}

// Gyroless acquisition at 4 deg/s (seed 004 Table 1.3; issue 16 item 4): the sample camera
// slewing (0.3, 4, 0.2) deg/s at 5 Hz for 6 s, 14 px streaks; the filter's rate prior set to
// the slew rate. After the first fix the filter's prediction of frame 2 is 0.8 deg wide
// (rate unknown to 4 deg/s over 0.2 s), beyond the largest window: frame 2 is solved
// lost-in-space from the streaks' shapes, the two fixes give the rate, and tracking carries
// every frame from the third. Measured: 30 of 30 frames solved, 28 tracking, 0 wrong valid
// outputs, 0 misidentified. Before (tracking with the 0.8 deg prediction): frames 2-5 failed,
// the filter coasted 1 s at a zero rate (4 deg off) and its first tracking step was wrong.
TEST(ReplayGyroless, AcquiresAtFourDegPerSecondFromTwoLostInSpaceFrames) {
  const std::string dir = test::makeTempDir("replay_gyroless_4dps");
  std::ifstream in(ini("slew_2dps.ini"));
  std::stringstream text;
  text << in.rdbuf();
  std::string scenario = text.str();
  scenario = std::regex_replace(scenario, std::regex(R"(\nduration_s +=.*)"), "\nduration_s = 6");
  scenario = std::regex_replace(scenario, std::regex(R"(\nframe_rate_hz +=.*)"), "\nframe_rate_hz = 5");
  scenario = std::regex_replace(scenario, std::regex(R"(\nrate_deg_s = .*)"), "\nrate_deg_s = 0.3 4 0.2");
  std::ofstream(dir + "/slew_4dps.ini") << scenario;
  std::ifstream tin(ini("gyroless_tracker.ini"));
  std::stringstream ttext;
  ttext << tin.rdbuf();
  const std::string tracker =
      std::regex_replace(ttext.str(), std::regex(R"(\nrate_sigma_deg_s = .*)"), "\nrate_sigma_deg_s = 4");
  ASSERT_NE(tracker, ttext.str());
  std::ofstream(dir + "/tracker.ini") << tracker;
  const std::string rawlog = dir + "/slew_4dps.rawlog", csv = dir + "/slew_4dps.csv";
  std::string out;
  ASSERT_EQ(test::runCommand(test::startrackerExe() + " simulate -q " + dir + "/slew_4dps.ini -o " +
                                 rawlog, &out), 0) << out;
  ASSERT_EQ(test::runCommand(test::startrackerExe() + " replay " + rawlog + " --config " + dir +
                                 "/tracker.ini --csv " + csv, &out), 0) << out;
  std::printf("%s\n", out.substr(out.find("frames:")).c_str());
  EXPECT_EQ(grab(out, R"(, (\d+) misidentified)"), 0) << out;
  EXPECT_EQ(grab(out, R"(integrity \(vs GROUND_TRUTH.*\): (\d+) wrong valid outputs)"), 0) << out;
  const auto rows = readCsvRows(csv);
  ASSERT_EQ(rows.size(), 30u);
  EXPECT_EQ(rows[0].at("mode"), "lost-in-space");
  EXPECT_EQ(rows[1].at("mode"), "lost-in-space");
  int tracking = 0;
  for (std::size_t i = 2; i < rows.size(); ++i) tracking += rows[i].at("mode") == "tracking";
  EXPECT_GE(tracking, 26);
  // The rate from the two lost-in-space fixes: within 3 sigma of the truth on y.
  const double ry = std::stod(rows[1].at("rate_y_deg_s")), sy = std::stod(rows[1].at("sigma_rate_y_deg_s"));
  EXPECT_NEAR(ry, 4.0, 3 * sy) << "sigma " << sy;
}

// Bad [filter] values of the gyroless keys: exit 2 with the file, section, key and value.
TEST(ReplayGyroless, BadGyrolessKeysAreInputErrorsNamingTheKey) {
  const std::string dir = test::makeTempDir("replay_gyroless_bad");
  const std::string rawlog = test::repoDir() + "/rawlogs/slew_2dps.rawlog";
  struct Case {
    std::string line, expect;
  };
  for (const Case& c : {Case{"model = gyrolss", "model"},
                        Case{"rate_walk_rad_s2_rt_hz = -1e-3", "rate_walk_rad_s2_rt_hz"},
                        Case{"rate_sigma_deg_s = 0", "rate_sigma_deg_s"}}) {
    const std::string ini = dir + "/bad.ini";
    std::ofstream(ini) << "[filter]\n" << c.line << "\n";
    std::string out;
    EXPECT_EQ(test::runCommand(test::startrackerExe() + " replay -q " + rawlog + " --config " + ini,
                               &out),
              2)
        << c.line << "\n" << out;
    EXPECT_NE(out.find(c.expect), std::string::npos) << out;
    EXPECT_NE(out.find("filter"), std::string::npos) << out;
  }
}

}  // namespace
}  // namespace st
