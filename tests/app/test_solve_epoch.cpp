// `solve --database` and the observation epoch (issue 21 item 2): a database holds stars at
// its own epoch and no proper motions, so one built for another epoch is refused, naming
// both epochs and the rebuild; one built for the frame's epoch solves and its epoch is
// printed. Also (item 11) the ids are named after the database's catalog: HR for BSC5.
#include <gtest/gtest.h>

#include <filesystem>

#include "tests/app/solve_cli_util.hpp"

namespace st {
namespace {

// The epoch of the tetra3 frames' file names (2019-07-29T20:47:26 UTC).
const std::string kFrameEpoch = "2019.5739";

std::string buildDatabase(const std::string& extra, const std::string& name) {
  static const std::string dir = test::makeTempDir("solve_epoch");
  const std::string path = dir + "/" + name;
  if (!std::filesystem::exists(path)) {
    std::string out;
    EXPECT_EQ(test::runCommand(test::startrackerExe() + " catalog build --fov-deg 15 " + extra +
                                   " -o " + path, &out), 0) << out;
  }
  return path;
}

std::string db2026() { return buildDatabase("--epoch 2026.9", "2026.db"); }
std::string dbOfFrame() { return buildDatabase("--epoch " + kFrameEpoch, "frame.db"); }

TEST(SolveEpoch, DatabaseOfAnotherEpochIsRefusedNamingBothAndTheRebuild) {
  const auto r = test::solveJson("--fov-deg 11.4 --database " + db2026() + " --epoch 2019.57 " +
                                 test::tetra3Frame());
  EXPECT_EQ(r.rc, 2) << r.stdout_text;
  ASSERT_FALSE(r.json.is_null()) << r.stdout_text;
  const std::string msg = r.json.at("error");
  for (const char* part : {"2019.5700", "2026.9000", "2026.db", "catalog build", "--epoch 2019.5700"})
    EXPECT_NE(msg.find(part), std::string::npos) << part << " not in: " << msg;
}

TEST(SolveEpoch, TheFileNamesEpochIsCheckedToo) {
  const auto r = test::solveJson("--fov-deg 11.4 --database " + db2026() + " " + test::tetra3Frame());
  EXPECT_EQ(r.rc, 2) << r.stdout_text;
  EXPECT_NE(r.json.at("error").get<std::string>().find("file name"), std::string::npos);
}

TEST(SolveEpoch, DatabaseOfTheFramesEpochSolvesAndPrintsItsEpoch) {
  const auto db = test::solveJson("--fov-deg 11.4 --database " + dbOfFrame() + " " + test::tetra3Frame());
  const auto mem = test::solveJson("--fov-deg 11.4 " + test::tetra3Frame());
  ASSERT_EQ(db.rc, 0) << db.stdout_text;
  ASSERT_EQ(mem.rc, 0) << mem.stdout_text;
  EXPECT_NEAR(db.json.at("database_epoch_jyear").get<double>(), 2019.5739, 1e-9);
  EXPECT_NEAR(db.json.at("epoch_jyear").get<double>(), 2019.5739, 1e-3);
  // Same stars at the same epoch (the file's V <= 6.5 vs the in-memory V <= 6.6): the
  // attitudes agree well within the 1-sigma (~5 arcsec cross-boresight, ~50 roll).
  EXPECT_LT(test::attitudeDifferenceArcsec(db.json, mem.json), 15.0);
  std::string text;
  ASSERT_EQ(test::runCommand(test::startrackerExe() + " solve --fov-deg 11.4 --database " +
                                 dbOfFrame() + " " + test::tetra3Frame(), &text), 0) << text;
  EXPECT_NE(text.find("epoch 2019.57"), std::string::npos) << text;
}

TEST(SolveEpoch, AnUndatedFrameTakesTheDatabasesEpoch) {
  const std::string undated = test::makeTempDir("solve_undated") + "/frame.tiff";
  std::filesystem::copy_file(test::tetra3Frame(), undated);
  const auto r = test::solveJson("--fov-deg 11.4 --database " + db2026() + " " + undated);
  ASSERT_EQ(r.rc, 0) << r.stdout_text;
  EXPECT_EQ(r.json.at("epoch_source"), "database");
  EXPECT_NEAR(r.json.at("epoch_jyear").get<double>(), 2026.9, 1e-9);
}

TEST(SolveCatalogIds, Bsc5StarsAreLabelledHr) {
  const std::string bsc = buildDatabase("--catalog " + test::bsc5Path() + " --epoch " + kFrameEpoch,
                                        "bsc5.db");
  const auto r = test::solveJson("--fov-deg 11.4 --database " + bsc + " " + test::tetra3Frame());
  ASSERT_EQ(r.rc, 0) << r.stdout_text;
  EXPECT_EQ(r.json.at("catalog_id"), "HR");
  EXPECT_EQ(r.json.at("stars")[0].at("name").get<std::string>().rfind("HR ", 0), 0u);
  std::string text;
  ASSERT_EQ(test::runCommand("(" + test::startrackerExe() + " solve --fov-deg 11.4 --database " +
                                 bsc + " " + test::tetra3Frame() + " 2>/dev/null)", &text), 0)
      << text;
  EXPECT_NE(text.find("      HR    x [px]"), std::string::npos) << text;
  EXPECT_EQ(text.find("HIP"), std::string::npos) << text;
  const auto hip = test::solveJson("--fov-deg 11.4 " + test::tetra3Frame());
  ASSERT_EQ(hip.rc, 0) << hip.stdout_text;
  EXPECT_EQ(hip.json.at("catalog_id"), "HIP");
}

}  // namespace
}  // namespace st
