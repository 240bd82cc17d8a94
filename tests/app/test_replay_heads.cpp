// Two camera heads on one body (issue 16 item 2), end to end through the commands a user runs:
// `simulate` renders rawlogs/two_heads.ini (head CAMERA along body +z, CAMERA2 along +x) and
// `replay` with rawlogs/two_heads_tracker.ini merges the heads' fixes of each time into one
// joint fix (sensors/attitude/joint_fix.hpp).
//  - one head knows its roll ~7x worse than its pointing; with the second head at 90 deg the
//    joint roll (about body z, head CAMERA's boresight) is within 1.5x head CAMERA's own
//    cross-boresight error, and the joint total is below the best single head's;
//  - the filter's NEES stays in its chi-square band (live_cli_util.hpp, with teeth);
//  - rawlogs/two_heads_blinded.ini: CAMERA2 saturated for 60 s: every frame keeps a fix from
//    CAMERA alone, accepted by the filter, and the heads merge again afterwards.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <regex>
#include <string>
#include <vector>

#include "tests/app/live_cli_util.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

struct HeadLine {
  double cross = -1, roll = -1, total = -1;
};

HeadLine headLine(const std::string& out, const std::string& prefix) {
  HeadLine h;
  std::smatch m;
  const std::regex re(prefix + R"(.*cross-boresight RMS ([0-9.]+), roll RMS ([0-9.]+), total RMS ([0-9.]+))");
  if (std::regex_search(out, m, re)) {
    h.cross = std::stod(m[1]);
    h.roll = std::stod(m[2]);
    h.total = std::stod(m[3]);
  }
  return h;
}

std::string simulate(const std::string& dir, const std::string& scenario, const std::string& extra) {
  const std::string rawlog = dir + "/" + scenario + ".rawlog";
  std::string out;
  EXPECT_EQ(test::runCommand(test::startrackerExe() + " simulate " + test::repoDir() +
                                 "/rawlogs/" + scenario + ".ini " + extra + " -o " + rawlog,
                             &out),
            0)
      << out;
  return rawlog;
}

/// Replays `rawlog` with rawlogs/two_heads_tracker.ini; its output (the CSV as dir/steps.csv).
std::string replayTwoHeads(const std::string& dir, const std::string& rawlog) {
  std::string out;
  EXPECT_EQ(test::runCommand(test::startrackerExe() + " replay -q " + rawlog + " --config " +
                                 test::repoDir() + "/rawlogs/two_heads_tracker.ini --csv " + dir +
                                 "/steps.csv",
                             &out),
            0)
      << out;
  return out;
}

TEST(ReplayHeads, JointFixBeatsEitherHeadAndRollIsNoLongerTheWeakAxis) {
  const std::string dir = test::makeTempDir("replay_heads");
  const std::string out = replayTwoHeads(dir, simulate(dir, "two_heads", "--frames 100"));
  const std::string csv = dir + "/steps.csv";
  const HeadLine one = headLine(out, "head CAMERA ");
  const HeadLine two = headLine(out, "head CAMERA2 ");
  const HeadLine joint = headLine(out, "joint fixes vs GROUND_TRUTH");
  std::printf("head CAMERA cross %.2f roll %.2f total %.2f; CAMERA2 total %.2f; joint cross %.2f "
              "roll %.2f total %.2f [arcsec]\n",
              one.cross, one.roll, one.total, two.total, joint.cross, joint.roll, joint.total);
  ASSERT_GT(one.cross, 0) << out;
  ASSERT_GT(joint.total, 0) << out;
  EXPECT_GT(one.roll, 3.0 * one.cross) << "one head's roll should be its weak axis\n" << out;
  EXPECT_LT(joint.roll, 1.5 * one.cross) << out;
  EXPECT_LT(joint.total, std::min(one.total, two.total)) << out;
  EXPECT_NE(out.find("joint fixes 100, heads disagreeing (not merged) 0"), std::string::npos) << out;
  EXPECT_NE(out.find(", 0 misidentified (claimed"), std::string::npos) << out;
  // The joint fixes' errors match their joint covariance: fixes are independent frame to
  // frame, so the fractions of their NEES below the chi2(3) median and 95 % point are
  // binomial (3 sigma of N); the same errors against a 4x optimistic covariance must fail.
  const std::vector<double> nees = test::csvColumn(csv, "fix_nees", "fix", 0);
  ASSERT_EQ(nees.size(), 100u);
  const double n = double(nees.size());
  const double tol50 = 3.0 * std::sqrt(0.25 / n), tol95 = 3.0 * std::sqrt(0.0475 / n);
  std::vector<double> optimistic(nees);
  for (double& v : optimistic) v *= 4.0;
  std::printf("joint fixes' NEES: %.3f below the chi2(3) median (+-%.3f), %.3f below its 95 %% "
              "point (+-%.3f); 4x optimistic: %.3f below the median\n",
              test::fractionBelow(nees, 0.5), tol50, test::fractionBelow(nees, 0.95), tol95,
              test::fractionBelow(optimistic, 0.5));
  EXPECT_NEAR(test::fractionBelow(nees, 0.5), 0.5, tol50);
  EXPECT_NEAR(test::fractionBelow(nees, 0.95), 0.95, tol95);
  EXPECT_GT(std::abs(test::fractionBelow(optimistic, 0.5) - 0.5), tol50);  // teeth
}

TEST(ReplayHeads, OneHeadBlindedForSixtySecondsKeepsTrackingOnTheOther) {
  const std::string dir = test::makeTempDir("replay_heads_blinded");
  const std::string out = replayTwoHeads(dir, simulate(dir, "two_heads_blinded", ""));
  const std::string csv = dir + "/steps.csv";
  int blinded = 0, blinded_one_head = 0, blinded_accepted = 0, after = 0, after_merged = 0;
  for (const auto& row : test::readCsvRows(csv)) {
    const double t = std::stod(row.at("t_s"));
    if (t > 10.5 && t < 70) {  // CAMERA2 saturated (blinding_start_s 10 .. end 70)
      ++blinded;
      blinded_one_head += row.at("heads_with_fix") == "1";
      blinded_accepted += row.at("update") == "accepted";
      EXPECT_EQ(row.at("misidentified"), "0") << "t = " << t;
    } else if (t > 71) {
      ++after;
      after_merged += row.at("heads_merged") == "1";
    }
  }
  std::printf("blinded: %d frames, %d with one head's fix, %d accepted; after: %d of %d merged\n",
              blinded, blinded_one_head, blinded_accepted, after_merged, after);
  EXPECT_EQ(blinded, 118);  // t = 11.0, 11.5, ..., 69.5
  EXPECT_EQ(blinded_one_head, blinded);  // CAMERA alone
  EXPECT_EQ(blinded_accepted, blinded);  // tracking never stopped
  EXPECT_GE(after, 16);
  EXPECT_EQ(after_merged, after);        // CAMERA2 back in the joint fix
  EXPECT_NE(out.find("integrity (vs GROUND_TRUTH, wrong = beyond 5 sigma + 5\" on an axis): 0 wrong "
                     "valid outputs"),
            std::string::npos)
      << out;
}

}  // namespace
}  // namespace st
