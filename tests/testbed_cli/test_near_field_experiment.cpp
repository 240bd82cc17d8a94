// `startracker montecarlo near-field` (seed 001 Tables 1-5): a small run writes the tables,
// the side-by-side table and the plots; a camera that cannot see the display is refused with
// exit 2 naming the flags.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/app/test_cli_run.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

namespace fs = std::filesystem;

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

TEST(NearFieldExperiment, SmallRunWritesTheSeedsTables) {
  const std::string dir = test::makeTempDir("mc_near_field");
  const auto r = test::runCli("montecarlo near-field --runs 10 --seed 3 --fov-deg 30 --size 640 "
                              "480 --noise-px 0.25 --no-plots --out out", dir);
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  const std::string base = dir + "/out/near-field";
  for (const char* f : {"_table_err0.csv", "_table_err+3.csv", "_table_err-3.csv",
                        "_table_err+6.csv", "_table_err-6.csv", "_table_updates.csv",
                        "_paper_vs_ours.csv", "_run.txt", ".md"})
    EXPECT_TRUE(fs::exists(base + f)) << f;
  // 5 one-update scenarios + 5 updates of the 2 deg one, per trial, plus the header
  std::ifstream t(base + "_trials.csv");
  int lines = 0;
  for (std::string l; std::getline(t, l);) ++lines;
  EXPECT_EQ(lines, 10 * 10 + 1);
  const std::string md = slurp(base + ".md");
  EXPECT_NE(md.find("Table 5: prediction off by 2 deg"), std::string::npos);
  EXPECT_NE(md.find("| err0 | stars matched | 7 |"), std::string::npos);
}

TEST(NearFieldExperiment, ACameraThatMissesTheDisplayIsRefused) {
  const auto r = test::runCli("montecarlo near-field --runs 10 --no-plots --out out");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--fov-deg 15"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace st
