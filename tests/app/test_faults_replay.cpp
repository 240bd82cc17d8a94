// Faults a flight tracker survives (issue 18 item 6): each rawlogs/fault_*.ini is a 20 s slew
// with one fault (sensors/sim/faults.hpp), simulated and replayed with the one-hour run's
// tracker. Replay must not crash, must report no wrong attitude as valid -- no estimate of
// the filter and no fix it takes off by more than 5 sigma + 5" on a body axis against the
// truth (app/live/integrity_summary.hpp) -- and its summary gives the longest time without a
// used fix and the longest without a filter estimate, from which the recovery time after the
// fault's end is read (the later of the two). Each case prints a row of the README's fault
// table.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "tests/support/test_paths.hpp"

namespace st {
namespace {

struct FaultCase {
  const char* name;
  double fault_start_s, fault_end_s;  ///< the window of faulty data (-1 -1: the whole run)
  int frames_affected;                ///< frames (or, for the gyro, frame intervals) faulted
  double max_recovery_s;  ///< bound on the measured recovery (see each case's comment)
};

void PrintTo(const FaultCase& c, std::ostream* os) { *os << c.name; }

class FaultReplay : public ::testing::TestWithParam<FaultCase> {};

TEST_P(FaultReplay, NoWrongValidAttitudeAndRecovers) {
  const FaultCase& c = GetParam();
  const std::string dir = test::makeTempDir(c.name);
  const std::string ini = test::repoDir() + "/rawlogs/" + c.name + ".ini";
  const std::string rawlog = dir + "/" + c.name + ".rawlog";
  const std::string exe = "'" + test::startrackerExe() + "'";
  std::string out;
  ASSERT_EQ(test::runCommand(exe + " simulate '" + ini + "' -o '" + rawlog + "'", &out), 0) << out;
  const int rc = test::runCommand(exe + " replay '" + rawlog + "' --config '" + test::repoDir() +
                                      "/rawlogs/one_hour_tracker.ini'",
                                  &out);
  ASSERT_EQ(rc, 0) << out;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(out, m, std::regex(R"(integrity .*: (\d+) wrong valid outputs)")))
      << out;
  const int wrong = std::stoi(m[1]);
  ASSERT_TRUE(std::regex_search(
      out, m,
      std::regex(R"(longest time without a used fix ([0-9.]+) s \(t = ([0-9.]+) to ([0-9.]+) s\))")))
      << out;
  const double outage = std::stod(m[1]), from = std::stod(m[2]), to = std::stod(m[3]);
  ASSERT_TRUE(std::regex_search(
      out, m,
      std::regex(
          R"(longest time without a filter estimate ([0-9.]+) s \(t = ([0-9.]+) to ([0-9.]+) s\))")))
      << out;
  const double blind = std::stod(m[1]), blind_from = std::stod(m[2]), blind_to = std::stod(m[3]);
  // Recovery: from the fault's end to the first fix used (or filter estimate given) after
  // it; 0 when the longest outage ended before the fault did (the fault never cost a frame
  // period more). A fault over the whole run: the longest outage itself.
  auto recoveryOf = [&c](double length, double a, double b) {
    if (c.fault_end_s < 0) return length;
    return b > c.fault_end_s && a < c.fault_end_s ? b - c.fault_end_s : 0.0;
  };
  const double recovery =
      std::max(recoveryOf(outage, from, to), recoveryOf(blind, blind_from, blind_to));
  std::printf("fault table: | %s | %d | %d | %.1f s (longest time without a used fix %.1f s, "
              "t = %.1f to %.1f s; without a filter estimate %.1f s, t = %.1f to %.1f s) |\n",
              c.name, c.frames_affected, wrong, recovery, outage, from, to, blind, blind_from,
              blind_to);
  EXPECT_EQ(wrong, 0) << out;
  EXPECT_LE(recovery, c.max_recovery_s) << out;
}

/// The one-hour run's tracker .ini with `lines` added under a [navigator] section.
std::string trackerIniWith(const std::string& dir, const std::string& lines) {
  std::ifstream in(test::repoDir() + "/rawlogs/one_hour_tracker.ini");
  std::stringstream text;
  text << in.rdbuf() << "\n[navigator]\n" << lines << "\n";
  const std::string path = dir + "/tracker.ini";
  std::ofstream(path) << text.str();
  return path;
}

// The health checks' teeth, and their ini keys in use: the stuck-axis run with the checks
// switched off (`gyro_health = false`) reports wrong attitudes as valid; a bad threshold
// exits 2 naming its key.
TEST(FaultReplayKeys, WithoutTheGyroHealthCheckAStuckAxisGivesWrongValidAttitudes) {
  const std::string dir = test::makeTempDir("fault_keys");
  const std::string rawlog = dir + "/stuck.rawlog";
  const std::string exe = "'" + test::startrackerExe() + "'";
  std::string out;
  ASSERT_EQ(test::runCommand(exe + " simulate '" + test::repoDir() +
                                 "/rawlogs/fault_gyro_stuck.ini' -o '" + rawlog + "'",
                             &out),
            0)
      << out;
  ASSERT_EQ(test::runCommand(exe + " replay '" + rawlog + "' --config '" +
                                 trackerIniWith(dir, "gyro_health = false") + "'",
                             &out),
            0)
      << out;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(out, m, std::regex(R"(integrity .*: (\d+) wrong valid outputs)")))
      << out;
  std::printf("stuck gyro axis without the health check: %s wrong valid outputs\n",
              m[1].str().c_str());
  EXPECT_GT(std::stoi(m[1]), 0) << out;

  const int rc = test::runCommand(exe + " replay '" + rawlog + "' --config '" +
                                      trackerIniWith(dir, "gyro_spike_sigmas = 0") + "' 2>&1",
                                  &out);
  EXPECT_EQ(rc, 2) << out;
  EXPECT_NE(out.find("gyro_spike_sigmas"), std::string::npos) << out;
  EXPECT_NE(out.find("must be > 0"), std::string::npos) << out;
}

// Recovery bounds. Camera faults: they cost the frames while they last; after the fault's
// end the next frame (0.1 s) is tracked again, or found by lost-in-space on the one after:
// 0.2 s, rounded up to 0.5 s for a frame whose stars are still near the blob's edge.
// Gyro faults (fusion/gyro_health.hpp): an axis stuck or noisy suspends the filter (frames
// lost-in-space, fixes unfiltered, hence no outage of used fixes); after the fault's end the
// axis' window statistics clear within half a window (10 samples, 0.1 s), then a full window
// of clean samples (20, 0.2 s), then the next lost-in-space frame (0.1 s) re-initialises the
// filter: 0.4 s, bounded at 0.5 s.
INSTANTIATE_TEST_SUITE_P(
    Faults, FaultReplay,
    ::testing::Values(
        // The Sun in the field (a saturated blob ~125 px across): frames lost while it is
        // there; fixes again once it leaves.
        FaultCase{"fault_sun", 8, 11, 30, 0.5},
        // The camera stops for 3 s and restarts; the gyro carries the filter across.
        FaultCase{"fault_camera_restart", 8, 11, 30, 0.5},
        // Gyro y axis stuck at its last reading for 5 s: found after 10 repeated readings
        // (t = 8.09 s) before the filter drifted past its bound; was 48 wrong filter steps of
        // 200 on 2026-12-01, before the health checks.
        FaultCase{"fault_gyro_stuck", 8, 13, 50, 0.5},
        // 2 deg/s of extra noise per sample on x for 5 s (80x the datasheet's 0.025 deg/s):
        // most samples are spikes, replaced, and the axis is found noisy after 4 of them in
        // 20 samples (t = 8.03 s); was 56 wrong.
        FaultCase{"fault_gyro_noisy", 8, 13, 50, 0.5},
        // 2 spikes/s of 5 deg/s on random axes over the whole run: each replaced by the
        // median of the 5 samples before it; no outage beyond a frame period. Was 122 wrong.
        FaultCase{"fault_gyro_spikes", -1, -1, 40, 0.5},
        // The camera repeats the image of t = 7.9 s for 2 s (fresh stamps): each repeat fails
        // as a frozen image (navigation/navigator.hpp), the gyro carries the filter across
        // and the first new image is tracked. Was 14 wrong.
        FaultCase{"fault_frozen", 8, 10, 20, 0.5},
        // The camera's clock jumps 1 s ahead at t = 8 s and back at 12 s: its frames arrive
        // stamped 1 s ahead of the gyro's timeline and are refused (fusion/fusion_loop.hpp);
        // the gyro carries the filter across. Was 14 wrong, partly a simulator artefact since
        // removed: `simulate` stamped the truth with the camera's clock too, so the filter's
        // estimate at a stamp was compared with the truth 1 s earlier. The truth now keeps
        // the true clock (the live simulated camera still stamps its truth with its own).
        FaultCase{"fault_time_jump", 8, 12, 40, 0.5}),
    [](const ::testing::TestParamInfo<FaultCase>& i) { return std::string(i.param.name); });

}  // namespace
}  // namespace st
