// common/output_file.hpp PendingOutput (issue 39: "outputs are written to a temporary name and
// renamed when complete, so an interrupted run never leaves a half file under the real name"):
// an output that is not committed leaves the real path as it was (an earlier run's file
// survives) and no temporary behind; a committed one replaces it whole.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/errors.hpp"
#include "common/output_file.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

namespace fs = std::filesystem;

TEST(PendingOutput, AnUncommittedOutputLeavesTheEarlierFileAndNoTemporary) {
  const std::string dir = test::makeTempDir("pending_output");
  const std::string path = dir + "/result.csv";
  std::ofstream(path) << "an earlier run's complete file\n";
  std::string temp;
  {
    PendingOutput out(path);
    temp = out.tempPath();
    EXPECT_EQ(fs::path(temp).parent_path(), fs::path(path).parent_path());
    EXPECT_EQ(fs::path(temp).extension(), ".csv");  // writers that pick a format by it
    std::ofstream(temp) << "half a new fi";
    // ... the run fails or is interrupted here: no commit.
  }
  EXPECT_EQ(test::fileBytes(path), "an earlier run's complete file\n");
  EXPECT_FALSE(fs::exists(temp));
}

TEST(PendingOutput, ACommittedOutputReplacesTheFileWhole) {
  const std::string dir = test::makeTempDir("pending_output_commit");
  const std::string path = dir + "/result.csv";
  std::ofstream(path) << "old\n";
  {
    PendingOutput out(path);
    std::ofstream(out.tempPath()) << "new\n";
    out.commit();
    EXPECT_FALSE(fs::exists(out.tempPath()));
  }
  EXPECT_EQ(test::fileBytes(path), "new\n");
  writeFileAtomically(path, std::string("third\n"));
  EXPECT_EQ(test::fileBytes(path), "third\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST(PendingOutput, AFolderThatCannotBeWrittenIsAnInputErrorNamingThePath) {
  EXPECT_THROW(writeFileAtomically("/proc/no-such-folder/x.csv", std::string("x")), InputError);
}

}  // namespace
}  // namespace st
