// End-to-end: `startracker solve` as a user runs it, on a real frame and on bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <regex>

#include "tests/support/test_paths.hpp"

namespace st {
namespace {

std::string realFrame() {
  return test::tetra3ImageDir() + "/2019-07-29T204726_Alt40_Azi-135_Try1.tiff";
}

double jsonNumber(const std::string& json, const std::string& key) {
  const std::regex re("\"" + key + "\":\\s*(-?[0-9.eE+-]+)");
  std::smatch m;
  if (!std::regex_search(json, m, re)) return std::nan("");
  return std::stod(m[1]);
}

TEST(SolveCli, RealFrameJsonHasTheDocumentedKeysAndTheKnownField) {
  std::string out;
  const int rc = test::runCommand(test::startrackerExe() + " solve --fov-deg 11.4 --json '" +
                                      realFrame() + "' 2>/dev/null",
                                  &out);
  ASSERT_EQ(rc, 0) << out;
  for (const char* key : {"\"ra_deg\"", "\"dec_deg\"", "\"roll_deg\"", "\"q_ib\"", "\"covariance\"",
                          "\"stars\"", "\"timing_ms\""})
    EXPECT_NE(out.find(key), std::string::npos) << key << " missing in " << out;
  // The tetra3 README gives the field centre of this frame: RA 230.7, Dec +11.0 deg.
  EXPECT_NEAR(jsonNumber(out, "ra_deg"), 230.7, 0.1);
  EXPECT_NEAR(jsonNumber(out, "dec_deg"), 11.0, 0.1);
  EXPECT_GE(jsonNumber(out, "stars_matched"), 10);
}

TEST(SolveCli, FovSearchWithoutCameraSolvesToo) {
  std::string out;
  const int rc = test::runCommand(test::startrackerExe() + " solve --json '" + realFrame() + "'", &out);
  ASSERT_EQ(rc, 0) << out;
  EXPECT_NEAR(jsonNumber(out, "dec_deg"), 11.0, 0.1);
}

TEST(SolveCli, BlackFrameExitsOneWithAReason) {
  const std::string path = test::makeTempDir("solve") + "/black.png";
  cv::imwrite(path, cv::Mat::zeros(480, 640, CV_8UC1));
  std::string out;
  EXPECT_EQ(test::runCommand(test::startrackerExe() + " solve --fov-deg 10 " + path, &out), 1) << out;
  EXPECT_NE(out.find("stars"), std::string::npos) << out;
}

TEST(SolveCli, BadInputExitsTwoNamingTheFile) {
  std::string out;
  EXPECT_EQ(test::runCommand(test::startrackerExe() + " solve --fov-deg 10 /no/such/image.png", &out), 2)
      << out;
  EXPECT_NE(out.find("/no/such/image.png"), std::string::npos) << out;
  const std::string dir = test::makeTempDir("solvebad");
  std::ofstream(dir + "/garbage.png") << "not an image";
  EXPECT_EQ(test::runCommand(test::startrackerExe() + " solve --fov-deg 10 " + dir + "/garbage.png", &out), 2)
      << out;
  EXPECT_NE(out.find("garbage.png"), std::string::npos) << out;
  EXPECT_EQ(test::runCommand(test::startrackerExe() + " solve --camera " + dir +
                                 "/nocam.yaml " + realFrame(),
                             &out),
            2)
      << out;
}

}  // namespace
}  // namespace st
