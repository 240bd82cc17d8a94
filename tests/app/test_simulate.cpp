// `startracker simulate` over an earlier run (issue 21 item 7c): an existing rawlog is
// replaced only with --force, and then no frame of the earlier run survives in <stem>_Images.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/test_paths.hpp"

namespace st {
namespace {

namespace fs = std::filesystem;

std::string simulate(const std::string& rawlog, const std::string& extra, int* rc) {
  std::string out;
  *rc = test::runCommand(test::startrackerExe() + " simulate " + test::repoDir() +
                             "/rawlogs/hold.ini --frames 2 -q -o " + rawlog + " " + extra,
                         &out);
  return out;
}

std::size_t filesIn(const std::string& dir) {
  std::size_t n = 0;
  for (const auto& e : fs::directory_iterator(dir)) n += e.is_regular_file();
  return n;
}

TEST(SimulateOverwrite, RefusesAnExistingRawlogWithoutForce) {
  const std::string dir = test::makeTempDir("simulate_overwrite");
  const std::string rawlog = dir + "/run.rawlog";
  int rc = 0;
  std::string out = simulate(rawlog, "", &rc);
  ASSERT_EQ(rc, 0) << out;
  const auto size = fs::file_size(rawlog);
  const auto mtime = fs::last_write_time(rawlog);

  out = simulate(rawlog, "", &rc);
  EXPECT_EQ(rc, 2) << out;
  EXPECT_NE(out.find(rawlog), std::string::npos) << out;
  EXPECT_NE(out.find("--force"), std::string::npos) << out;
  EXPECT_EQ(fs::file_size(rawlog), size);
  EXPECT_EQ(fs::last_write_time(rawlog), mtime);
  EXPECT_EQ(filesIn(dir + "/run_Images"), 2u);

  // Images of an earlier run without its rawlog are an earlier run too.
  fs::remove(rawlog);
  out = simulate(rawlog, "", &rc);
  EXPECT_EQ(rc, 2) << out;
  EXPECT_NE(out.find("run_Images"), std::string::npos) << out;
}

TEST(SimulateOverwrite, ForceEmptiesTheImagesFolderSoNoStaleFrameSurvives) {
  const std::string dir = test::makeTempDir("simulate_force");
  const std::string rawlog = dir + "/run.rawlog";
  int rc = 0;
  std::string out = simulate(rawlog, "", &rc);
  ASSERT_EQ(rc, 0) << out;
  // A longer earlier run left a frame the new one does not make.
  std::ofstream(dir + "/run_Images/CAMERA_000099.png") << "stale";
  out = simulate(rawlog, "--force", &rc);
  EXPECT_EQ(rc, 0) << out;
  EXPECT_FALSE(fs::exists(dir + "/run_Images/CAMERA_000099.png"));
  EXPECT_EQ(filesIn(dir + "/run_Images"), 2u);
  out = simulate(rawlog, "-f --inline-images", &rc);
  EXPECT_EQ(rc, 0) << out;
  EXPECT_TRUE(!fs::exists(dir + "/run_Images") || filesIn(dir + "/run_Images") == 0u);
}

// `replay -o out.rawlog` links out_Images to the input's folder: --force onto out.rawlog must
// remove the link, never the input's frames behind it.
TEST(SimulateOverwrite, ForceRemovesALinkedImagesFolderNotItsTarget) {
  const std::string dir = test::makeTempDir("simulate_link");
  fs::create_directory(dir + "/other_Images");
  std::ofstream(dir + "/other_Images/CAMERA_000000.png") << "another rawlog's frame";
  fs::create_directory_symlink(dir + "/other_Images", dir + "/run_Images");
  std::ofstream(dir + "/run.rawlog") << "an earlier output";
  int rc = 0;
  const std::string out = simulate(dir + "/run.rawlog", "--force", &rc);
  EXPECT_EQ(rc, 0) << out;
  EXPECT_TRUE(fs::exists(dir + "/other_Images/CAMERA_000000.png"));
  EXPECT_FALSE(fs::is_symlink(dir + "/run_Images"));
  EXPECT_EQ(filesIn(dir + "/run_Images"), 2u);
}

TEST(SimulateOverwrite, UnwritableOutputFailsBeforeSimulating) {
  const std::string dir = test::makeTempDir("simulate_badout");
  std::ofstream(dir + "/afile") << "a file, not a folder\n";
  int rc = 0;
  const std::string out = simulate(dir + "/afile/run.rawlog", "", &rc);
  EXPECT_EQ(rc, 2) << out;
  EXPECT_NE(out.find("-o"), std::string::npos) << out;
  EXPECT_NE(out.find(dir + "/afile/run.rawlog"), std::string::npos) << out;
}

}  // namespace
}  // namespace st
