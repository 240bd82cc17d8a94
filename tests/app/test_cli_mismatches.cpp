// Issue 39, "smaller mismatches", through the real program: `camera FILE` works as `camera
// --camera FILE`; `calibrate` skips an unreadable frame as solve does instead of ending; with
// --database the timing's total holds its database part; -v says per frame what happened.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/app/test_cli_run.hpp"

namespace st {
namespace {

namespace fs = std::filesystem;

std::string camFile() { return "'" + test::repoDir() + "/docs/inflight/swarm_stra_calibrated.yaml'"; }

TEST(CliMismatches, CameraTakesTheFileAsAnArgument) {
  const test::CliRun plain = test::runCli("camera " + camFile());
  const test::CliRun flag = test::runCli("camera --camera " + camFile());
  EXPECT_EQ(plain.code, 0) << plain.err;
  EXPECT_EQ(plain.out, flag.out);
  EXPECT_THAT(plain.out, ::testing::HasSubstr("752x290 px"));
  const test::CliRun both = test::runCli("camera " + camFile() + " --camera " + camFile());
  EXPECT_EQ(both.code, 2) << both.err;
  EXPECT_THAT(both.err, ::testing::HasSubstr("give the camera file once"));
}

TEST(CliMismatches, CalibrateSkipsAnUnreadableFrame) {
  const std::string dir = test::makeTempDir("calibrate_skip");
  fs::create_directory(dir + "/frames");
  const auto frames = test::tetra3Frames();
  for (std::size_t k = 0; k < 4; ++k)
    fs::copy_file(frames[k], dir + "/frames/f" + std::to_string(k) + ".tiff");
  std::ofstream(dir + "/frames/f9_damaged.tiff") << "II*\0 not a TIFF";
  const test::CliRun r = test::runCli("calibrate frames --fov-deg 11.4 -o cam.yaml -v", dir);
  EXPECT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_THAT(r.err, ::testing::HasSubstr("f9_damaged.tiff"));
  EXPECT_THAT(r.err, ::testing::HasSubstr("skipped"));
  EXPECT_THAT(r.out, ::testing::HasSubstr("(4 of 5 frames solved, 1 unreadable skipped)"));
  // -v: detection and identification of each frame.
  EXPECT_THAT(r.err, ::testing::HasSubstr("f0.tiff: "));
  EXPECT_THAT(r.err, ::testing::HasSubstr("stars detected"));
  EXPECT_THAT(r.err, ::testing::HasSubstr("identified"));
}

TEST(CliMismatches, TheTimingTotalHoldsTheDatabaseItWasGiven) {
  const std::string dir = test::makeTempDir("timing_total");
  ASSERT_EQ(test::runCli("catalog build --fov-deg 11.4 --size 1024 768 --epoch 2019.57 -o db.bin", dir).code, 0);
  const test::CliRun r = test::runCli(
      "solve '" + test::tetra3Frames().front() + "' --fov-deg 11.4 --database db.bin --json", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const auto& t = j.at("timing_ms");
  EXPECT_GT(t.at("database").get<double>(), 0);
  EXPECT_GE(t.at("total").get<double>(), t.at("database").get<double>()) << t.dump();
}

TEST(CliMismatches, VerboseReplaySaysWhatEachFrameDid) {
  const test::CliRun r = test::runCli("replay '" + test::repoDir() + "/rawlogs/hold.rawlog' -v");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(r.err, ::testing::HasSubstr("t = 0.000 s: "));
  EXPECT_THAT(r.err, ::testing::HasSubstr("stars matched"));
}

}  // namespace
}  // namespace st
