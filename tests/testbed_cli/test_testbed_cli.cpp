// `startracker testbed draw | photograph | solve` end to end: the sky drawn for a screen,
// photographed by the simulated camera at a platform attitude, solved back to that attitude
// with --json; bad geometry and a missing star list exit 2 naming the flag or file.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "tests/app/test_cli_run.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

TEST(TestbedCli, DrawPhotographSolveRoundTrip) {
  const std::string dir = test::makeTempDir("testbed_cli");
  auto run = [&](const std::string& args) { return test::runCli(args, dir); };
  const auto draw = run("testbed draw --attitude-ypr-deg 30 40 10 --mag-limit 5 -o screen.png");
  ASSERT_EQ(draw.code, 0) << draw.err;
  const auto photo = run("testbed photograph screen.png --fov-deg 30 --attitude-ypr-deg 1 -2 0.5 "
                         "-o cam.png");
  ASSERT_EQ(photo.code, 0) << photo.err;
  const auto solve = run("testbed solve cam.png --fov-deg 30 --stars screen.csv --json");
  ASSERT_EQ(solve.code, 0) << solve.err << solve.out;
  const auto j = nlohmann::json::parse(solve.out);
  ASSERT_EQ(j.size(), 1u);
  ASSERT_TRUE(j[0]["ok"].get<bool>());
  ASSERT_EQ(j[0]["updates"].size(), 3u);  // default --iterations 3
  EXPECT_GE(j[0]["updates"][2]["stars_matched"].get<int>(), 4);
  const auto ypr = j[0]["platform_ypr_deg"];
  EXPECT_NEAR(ypr[0].get<double>(), 1.0, 0.02);  // degrees; a camera pixel is 0.047 deg
  EXPECT_NEAR(ypr[1].get<double>(), -2.0, 0.02);
  EXPECT_NEAR(ypr[2].get<double>(), 0.5, 0.02);
}

TEST(TestbedCli, BadInputExitsTwoNamingIt) {
  const std::string dir = test::makeTempDir("testbed_cli_bad");
  const auto lever = test::runCli("testbed draw --lever-arm-m 0 0 5 -o x.png", dir);
  EXPECT_EQ(lever.code, 2);
  EXPECT_NE(lever.err.find("--lever-arm-m"), std::string::npos) << lever.err;
  const auto list = test::runCli("testbed solve x.png --fov-deg 30 --stars nope.csv", dir);
  EXPECT_EQ(list.code, 2);
  EXPECT_NE(list.err.find("nope.csv"), std::string::npos) << list.err;
  const auto iters = test::runCli("testbed solve x.png --fov-deg 30 --stars s.csv --iterations 0",
                                  dir);
  EXPECT_EQ(iters.code, 2);
  EXPECT_NE(iters.err.find("--iterations"), std::string::npos) << iters.err;
}

}  // namespace
}  // namespace st
