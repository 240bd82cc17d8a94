// Issue 39, deliverable 1: one output policy for every command. An existing file at an output
// path is refused before any work (exit 2, naming the flag, the path and -f/--force) and left
// as it was; with -f/--force it is replaced. Each command below used to overwrite it in
// silence (`solve --annotate`, `calibrate -o`, `replay --csv`, ...).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/app/test_cli_run.hpp"

namespace st {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const char* const kEarlier = "an earlier run's result";

struct Case {
  std::string args;    ///< the command, without -f
  std::string output;  ///< the output file it writes, relative to the folder
  std::string flag;    ///< what the refusal names
};

/// A folder with three real frames in frames/, a database for them, a camera file and a
/// tracker recording: what the commands below read.
std::string workFolder() {
  const std::string dir = test::makeTempDir("existing_outputs");
  fs::create_directory(dir + "/frames");
  const auto frames = test::tetra3Frames();
  for (std::size_t k = 0; k < 3; ++k)
    fs::copy_file(frames[k], dir + "/frames/" + fs::path(frames[k]).filename().string());
  fs::copy_file(test::repoDir() + "/rawlogs/hold.rawlog", dir + "/X.rawlog");
  fs::create_directory_symlink(test::repoDir() + "/rawlogs/hold_Images", dir + "/X_Images");
  return dir;
}

TEST(ExistingOutputs, AreRefusedWithoutForceAndReplacedWithIt) {
  const std::string dir = workFolder();
  const std::string frame = "frames/" + fs::path(test::tetra3Frames().front()).filename().string();
  const std::vector<Case> cases = {
      {"solve " + frame + " --fov-deg 11.4 --annotate a.png", "a.png", "--annotate"},
      {"solve " + frame + " --fov-deg 11.4 --wcs a.wcs", "a.wcs", "--wcs"},
      {"solve " + frame + " --fov-deg 11.4 -o r.jsonl", "r.jsonl", "-o"},
      {"calibrate frames --fov-deg 11.4 -o cam.yaml", "cam.yaml", "-o"},
      {"camera --fov-deg 11.4 --size 1024 768 --save cam2.yaml", "cam2.yaml", "--save"},
      {"catalog build --fov-deg 11.4 --size 1024 768 -o db.bin", "db.bin", "--output"},
      {"replay X.rawlog --csv t.csv", "t.csv", "--csv"},
      {"replay X.rawlog -o Y.rawlog", "Y.rawlog", "-o/--output"},
      {"testbed draw -o screen.png", "screen.png", "-o/--output"},
  };
  for (const Case& c : cases) {
    std::ofstream(dir + "/" + c.output) << kEarlier;
    const test::CliRun refused = test::runCli(c.args, dir);
    EXPECT_EQ(refused.code, 2) << c.args << "\n" << refused.err;
    EXPECT_THAT(refused.err, HasSubstr(c.flag + " " + c.output)) << c.args;
    EXPECT_THAT(refused.err, HasSubstr("-f")) << c.args;
    EXPECT_EQ(test::fileBytes(dir + "/" + c.output), kEarlier) << c.args << ": changed";
    const test::CliRun forced = test::runCli(c.args + " -f", dir);
    EXPECT_EQ(forced.code, 0) << c.args << " -f\n" << forced.err;
    EXPECT_NE(test::fileBytes(dir + "/" + c.output), kEarlier) << c.args << " -f: not replaced";
  }
}

TEST(ExistingOutputs, DarkAndTheTestbedStarListAndMergeToo) {
  const std::string dir = workFolder();
  // dark: the median of at least three frames.
  std::ofstream(dir + "/dark.fits") << kEarlier;
  const test::CliRun dark = test::runCli("dark frames -o dark.fits", dir);
  EXPECT_EQ(dark.code, 2) << dark.err;
  EXPECT_THAT(dark.err, HasSubstr("-o/--output dark.fits: the file exists"));
  EXPECT_EQ(test::fileBytes(dir + "/dark.fits"), kEarlier);
  // testbed draw writes a star list beside its image: an earlier list is not lost either.
  std::ofstream(dir + "/s.csv") << kEarlier;
  const test::CliRun draw = test::runCli("testbed draw -o s.png", dir);
  EXPECT_EQ(draw.code, 2) << draw.err;
  EXPECT_THAT(draw.err, HasSubstr("star list s.csv: the file exists"));
  EXPECT_FALSE(fs::exists(dir + "/s.png"));
  // solve merge's output.
  ASSERT_EQ(test::runCli("solve frames --fov-deg 11.4 -o part.jsonl", dir).code, 0);
  std::ofstream(dir + "/all.jsonl") << kEarlier;
  const test::CliRun merge = test::runCli("solve merge part.jsonl -o all.jsonl", dir);
  EXPECT_EQ(merge.code, 2) << merge.err;
  EXPECT_EQ(test::fileBytes(dir + "/all.jsonl"), kEarlier);
  EXPECT_EQ(test::runCli("solve merge part.jsonl -o all.jsonl -f", dir).code, 0);
  EXPECT_NE(test::fileBytes(dir + "/all.jsonl"), kEarlier);
}

}  // namespace
}  // namespace st
