// Faults a flight tracker survives (issue 18 item 6): each rawlogs/fault_*.ini is a 20 s slew
// with one fault (sensors/sim/faults.hpp), simulated and replayed with the one-hour run's
// tracker. Replay must not crash, must report no wrong attitude as valid -- no estimate of
// the filter and no fix it takes off by more than 5 sigma + 5" on a body axis against the
// truth (app/live/integrity_summary.hpp) -- and its summary gives the longest time without a
// used fix, from which the recovery time after the fault's end is read. Each case prints a
// row of the README's fault table.
#include <gtest/gtest.h>

#include <cstdio>
#include <regex>
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
  // Recovery: from the fault's end to the first fix used after it; 0 when the longest outage
  // ended before the fault did (the fault never cost a frame period more). A fault over the
  // whole run: the longest outage itself.
  double recovery = outage;
  if (c.fault_end_s >= 0) recovery = to > c.fault_end_s && from < c.fault_end_s ? to - c.fault_end_s : 0.0;
  std::printf("fault table: | %s | %d | %d | %.1f s (longest time without a used fix %.1f s, "
              "t = %.1f to %.1f s) |\n",
              c.name, c.frames_affected, wrong, recovery, outage, from, to);
  EXPECT_EQ(wrong, 0) << out;
  EXPECT_LE(recovery, c.max_recovery_s) << out;
}

// Recovery bounds: the camera faults cost the frames while they last; after the fault's end
// the next frame (0.1 s) is tracked again, or found by lost-in-space on the one after: 0.2 s,
// rounded up to 0.5 s for a frame whose stars are still near the blob's edge.
INSTANTIATE_TEST_SUITE_P(
    Faults, FaultReplay,
    ::testing::Values(
        // The Sun in the field (a saturated blob ~125 px across): frames lost while it is
        // there; fixes again once it leaves.
        FaultCase{"fault_sun", 8, 11, 30, 0.5},
        // The camera stops for 3 s and restarts; the gyro carries the filter across.
        FaultCase{"fault_camera_restart", 8, 11, 30, 0.5}),
    [](const ::testing::TestParamInfo<FaultCase>& i) { return std::string(i.param.name); });

// Faults the tracker does NOT survive yet (issue 18 item 6, open): replayed on 2026-12-01
// they report wrong attitudes as valid. The gyro faults: the filter trusts the gyro's
// datasheet noise, refuses the (correct) fixes with its gate and reports its drifting
// estimate until three refusals re-initialise it, again and again (stuck y axis: 48 wrong
// filter steps of 200; 2 deg/s noise on x: 56; 2 spikes/s of 5 deg/s: 122). Frozen images:
// the refusals re-initialise the filter from a lost-in-space fix of the frozen image (14).
// Camera clock jumps: fixes stamped 1 s late are refused, the filter's estimate at the frame's
// stamp is compared with the truth stamped alike (14). Needed: gyro health checks (a sample
// or axis against its neighbours and the fixes) in the fusion loop, a frozen-image check
// (a frame identical to the previous one) in the tracker, a camera-clock check against the
// gyro's. Enable with --gtest_also_run_disabled_tests.
INSTANTIATE_TEST_SUITE_P(
    DISABLED_FaultsNotYetSurvived, FaultReplay,
    ::testing::Values(FaultCase{"fault_gyro_stuck", 8, 13, 50, 0.5},
                      FaultCase{"fault_gyro_noisy", 8, 13, 50, 0.5},
                      FaultCase{"fault_gyro_spikes", -1, -1, 40, 0.5},
                      FaultCase{"fault_frozen", 8, 10, 20, 0.5},
                      FaultCase{"fault_time_jump", 8, 12, 40, 0.5}),
    [](const ::testing::TestParamInfo<FaultCase>& i) { return std::string(i.param.name); });

}  // namespace
}  // namespace st
