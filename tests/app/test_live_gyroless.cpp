// `startracker live` without a gyro (issue 16 item 3): rawlogs/live_sim.ini with its
// GYRO_SENSOR removed and [filter] model = gyroless runs the same fusion loop as replay on
// STAR_TRACKER fixes alone; the rawlog holds no GYRO observation, the tracker tracks on the
// filter's prediction, and the summary reports the rate against the truth.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "sensors/mrpt/rawlog_io.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

/// live_sim.ini without its [GYRO_SENSOR] section, its [filter] gyroless.
std::string gyrolessLiveIni(const std::string& dir) {
  std::ifstream in(test::repoDir() + "/rawlogs/live_sim.ini");
  std::ostringstream out;
  bool skip = false;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] == '[') skip = line == "[GYRO_SENSOR]";
    if (skip) continue;
    out << line << "\n";
    if (line == "[filter]") out << "model = gyroless\nrate_sigma_deg_s = 1\n";
  }
  const std::string path = dir + "/live_sim.ini";  // scenario_file = live_sim.ini: same folder
  std::ofstream(path) << out.str();
  return path;
}

double grab(const std::string& out, const std::string& pattern) {
  std::smatch m;
  if (!std::regex_search(out, m, std::regex(pattern))) return -1;
  return std::stod(m[1]);
}

// 20 s: the database build takes a few of them; at 10 Hz that leaves > 100 frames.
TEST(LiveGyroless, RunsWithoutAGyroOnTheSameLoopAndReportsTheRate) {
  const std::string dir = test::makeTempDir("live_gyroless");
  const std::string ini = gyrolessLiveIni(dir);
  const std::string rawlog = dir + "/out.rawlog";
  std::string out;
  const int rc = test::runCommand("timeout --preserve-status -s INT 20 '" +
                                      test::startrackerExe() + "' live '" + ini + "' -o '" +
                                      rawlog + "'",
                                  &out);
  ASSERT_EQ(rc, 0) << out;
  std::size_t gyro = 0, fixes = 0;
  for (const auto& o : readRawlog(rawlog)) {
    gyro += o->sensorLabel == "GYRO";
    fixes += o->sensorLabel == "STAR_TRACKER";
  }
  EXPECT_EQ(gyro, 0u) << out;
  ASSERT_GE(fixes, 50u) << out;
  const double tracking = grab(out, R"(star tracker: \d+ frames, \d+ solved .*, (\d+) tracking)");
  EXPECT_GE(tracking, 0.9 * double(fixes)) << out;
  EXPECT_NE(out.find("filter rate (gyroless state) error RMS"), std::string::npos) << out;
  EXPECT_EQ(grab(out, R"(, (\d+) misidentified)"), 0) << out;
  std::printf("%s\n", out.substr(out.find("body rate vs")).c_str());
}

}  // namespace
}  // namespace st
