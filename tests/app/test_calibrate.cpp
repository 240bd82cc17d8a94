// `startracker calibrate` on the eight real tetra3 frames: the camera file it writes makes
// `solve --camera` solve all eight with a lower median residual than the per-frame sky fit
// (no camera file); bad input is refused with exit code 2 naming it.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "tests/app/solve_cli_util.hpp"

namespace st {
namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

TEST(Calibrate, CalibratedCameraSolvesTheEightFramesWithLowerResiduals) {
  const std::string dir = test::makeTempDir("calibrate");
  const std::string cam = dir + "/camera.yaml";
  std::string out;
  ASSERT_EQ(test::runCommand(test::startrackerExe() + " calibrate -q " +
                                 test::shellQuote(test::tetra3ImageDir()) + " -o " + cam + " 2>&1",
                             &out),
            0)
      << out;
  EXPECT_NE(out.find("8 of 8 frames solved"), std::string::npos) << out;
  std::vector<double> with, without;
  for (const std::string& frame : test::tetra3Frames()) {
    const auto a = test::solveJson("--camera " + cam + " " + test::shellQuote(frame));
    const auto b = test::solveJson(test::shellQuote(frame));
    ASSERT_EQ(a.rc, 0) << a.stdout_text;
    ASSERT_EQ(b.rc, 0) << b.stdout_text;
    with.push_back(a.json.at("rms_residual_px").get<double>());
    without.push_back(b.json.at("rms_residual_px").get<double>());
  }
  ASSERT_EQ(with.size(), 8u);
  EXPECT_LT(median(with), median(without));
}

TEST(Calibrate, BadInputIsRefusedNamingIt) {
  const std::string dir = test::makeTempDir("calibrate_bad");
  std::string out;
  EXPECT_EQ(test::runCommand(test::startrackerExe() + " calibrate " + dir + " -o " + dir +
                                 "/c.yaml 2>&1",
                             &out),
            2);
  EXPECT_NE(out.find("no images"), std::string::npos) << out;
  EXPECT_EQ(test::runCommand(test::startrackerExe() + " calibrate " + dir + "/missing.tiff -o " +
                                 dir + "/c.yaml 2>&1",
                             &out),
            2);
  EXPECT_NE(out.find("missing.tiff: no such file"), std::string::npos) << out;
}

}  // namespace
}  // namespace st
