// The CLI's exit codes and messages on bad usage and bad camera files (issue 2):
// 0 success, 1 processing failure, 2 bad usage or bad input; the message names the input.
#include <gtest/gtest.h>

#include <fstream>

#include "tests/support/test_paths.hpp"

namespace st {
namespace {

std::string exe() { return test::startrackerExe(); }

TEST(CliErrors, VersionAndHelpExitZero) {
  std::string out;
  EXPECT_EQ(test::runCommand(exe() + " --version", &out), 0);
  EXPECT_NE(out.find("startracker"), std::string::npos);
  for (const char* cmd : {"camera", "catalog", "solve", "simulate", "replay", "live", "montecarlo"})
    EXPECT_EQ(test::runCommand(exe() + " " + cmd + " --help", &out), 0) << cmd << ": " << out;
}

TEST(CliErrors, BadUsageExitsTwo) {
  std::string out;
  EXPECT_EQ(test::runCommand(exe(), &out), 2) << out;
  EXPECT_EQ(test::runCommand(exe() + " no-such-command", &out), 2) << out;
  EXPECT_EQ(test::runCommand(exe() + " camera --fov-deg -3 --size 640 480", &out), 2) << out;
}

TEST(CliErrors, BadCameraFilesExitTwoNamingFileAndKey) {
  const std::string dir = test::makeTempDir("clicam");
  struct Case {
    std::string name, text, needle;
  };
  const std::string dist =
      "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n"
      "   data: [0, 0, 0, 0, 0]\n";
  const std::vector<Case> cases = {
      {"missing_key.yaml", "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n" + dist,
       "camera_matrix"},
      {"negative_f.yaml",
       "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
       "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
       "   data: [-500, 0, 320, 0, 500, 240, 0, 0, 1]\n" + dist,
       "focal"},
  };
  for (const Case& c : cases) {
    const std::string path = dir + "/" + c.name;
    std::ofstream(path) << c.text;
    std::string out;
    EXPECT_EQ(test::runCommand(exe() + " camera --camera " + path, &out), 2) << out;
    EXPECT_NE(out.find(path), std::string::npos) << out;
    EXPECT_NE(out.find(c.needle), std::string::npos) << out;
  }
  std::string out;
  EXPECT_EQ(test::runCommand(exe() + " camera --camera " + dir + "/does_not_exist.yaml", &out), 2);
  EXPECT_NE(out.find("does_not_exist.yaml"), std::string::npos) << out;
  // A good file round-trips through --save and loads again with exit 0.
  EXPECT_EQ(test::runCommand(exe() + " camera --fov-deg 12 --size 1024 768 --save " + dir +
                                 "/good.yaml",
                             &out),
            0)
      << out;
  EXPECT_EQ(test::runCommand(exe() + " camera --camera " + dir + "/good.yaml", &out), 0) << out;
}

}  // namespace
}  // namespace st
