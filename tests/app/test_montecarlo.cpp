// End-to-end tests of `startracker montecarlo`: every experiment runs small and writes its
// files; a 2-way sharded run merged equals the unsharded run byte for byte; the thread count
// does not change results; bad input gives exit 2 with a clear message; a missing gnuplot
// gives exit 1 after the tables are written.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/support/test_paths.hpp"

namespace st {
namespace {

namespace fs = std::filesystem;

std::string readFile(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::size_t lineCount(const std::string& path) {
  const std::string s = readFile(path);
  return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
}

int mc(const std::string& args, std::string* out = nullptr) {
  std::string o;
  const int rc = test::runCommand(test::startrackerExe() + " montecarlo " + args + " -q", &o);
  if (out) *out = o;
  if (rc != 0 && rc != 2) ADD_FAILURE() << "montecarlo " << args << " -> " << rc << "\n" << o;
  return rc;
}

bool haveGnuplot() { return test::runCommand("gnuplot --version") == 0; }

struct Case {
  std::string experiment, args;
  std::size_t rows;  // trial rows expected
  std::vector<std::string> files;
};

TEST(Montecarlo, EveryExperimentWritesTablesAndPlots) {
  const std::string dir = test::makeTempDir("mc_all");
  const bool plots = haveGnuplot();
  const std::vector<Case> cases = {
      {"star-count", "--runs 40", 40, {"_histogram.csv", "_per_mag.csv", "_histogram.png", "_per_mag.png"}},
      {"fov-selection", "--runs 30 --fovs 5,10,20 --mags 5,6", 60,
       {"_probabilities.csv", "_fov_needed.csv", "_p_lt3.png", "_fov_needed.png"}},
      {"lis-robustness", "--runs 2 --algorithms pyramid,voting", 2 * 20 * 2,
       {"_situations.csv", "_vs_false_stars.png", "_vs_dropped.png", "_vs_noise.png"}},
      {"error-vs-stars", "--runs 5 --solvers quest,triad", 0, {"_errors.csv", "_cross.png", "_roll.png", "_nees.png"}},
      {"timing", "--runs 3", 6, {"_overall.csv", "_by_stars.csv", "_stages.png"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.experiment);
    std::string out;
    const std::string args = c.experiment + " " + c.args + " --out " + dir +
                             (plots ? "" : " --no-plots");
    ASSERT_EQ(mc(args, &out), 0) << out;
    const std::string base = dir + "/" + c.experiment;
    for (const std::string& f : {std::string(".md"), std::string("_trials.csv"),
                                 std::string("_run.txt")})
      EXPECT_TRUE(fs::exists(base + f)) << base + f;
    for (const std::string& f : c.files) {
      if (!plots && f.size() > 4 && f.substr(f.size() - 4) == ".png") continue;
      ASSERT_TRUE(fs::exists(base + f)) << base + f;
      EXPECT_GT(fs::file_size(base + f), 20u) << base + f;
    }
    if (c.rows) {
      EXPECT_EQ(lineCount(base + "_trials.csv"), c.rows + 1);
    }
    // The Markdown report carries the reproducing command and a table.
    const std::string md = readFile(base + ".md");
    EXPECT_NE(md.find("startracker montecarlo " + c.experiment), std::string::npos);
    EXPECT_NE(md.find("|---|"), std::string::npos);
  }
  // Content sanity: in the nominal situation with 0.1 px noise, pyramid never reports a wrong
  // attitude (the false-ID column is 0 in every row of the trial table).
  const std::string trials = readFile(dir + "/lis-robustness_trials.csv");
  EXPECT_EQ(trials.find(",1,1,"), std::string::npos) << "a solved false ID (solved=1,false_id=1)";
}

void expectSameFiles(const std::string& a, const std::string& b,
                     const std::vector<std::string>& names) {
  for (const std::string& n : names) {
    SCOPED_TRACE(n);
    const std::string fa = readFile(a + "/" + n), fb = readFile(b + "/" + n);
    ASSERT_FALSE(fa.empty()) << a + "/" + n;
    EXPECT_EQ(fa, fb);
  }
}

TEST(Montecarlo, TwoShardsMergedEqualUnsharded) {
  const std::string whole = test::makeTempDir("mc_whole"), shards = test::makeTempDir("mc_shards"),
                    merged = test::makeTempDir("mc_merged");
  const std::string common = "lis-robustness --runs 5 --algorithms pyramid,liebe --seed 42 --no-plots";
  ASSERT_EQ(mc(common + " --out " + whole), 0);
  ASSERT_EQ(mc(common + " --shard 0/2 --out " + shards), 0);
  ASSERT_TRUE(fs::exists(shards + "/lis-robustness_trials.shard-0-of-2.csv"));
  // Teeth: one shard alone does not merge.
  std::string out;
  EXPECT_EQ(mc("merge " + shards + " --no-plots --out " + merged, &out), 2);
  EXPECT_NE(out.find("1 of 2 shards"), std::string::npos) << out;
  ASSERT_EQ(mc(common + " --shard 1/2 --out " + shards), 0);
  ASSERT_EQ(mc("merge " + shards + " --no-plots --out " + merged), 0);
  expectSameFiles(whole, merged,
                  {"lis-robustness_trials.csv", "lis-robustness_situations.csv",
                   "lis-robustness.md", "lis-robustness_run.txt"});
  // The same for a catalog-only experiment, shards in two directories.
  const std::string s0 = test::makeTempDir("mc_s0"), s1 = test::makeTempDir("mc_s1");
  const std::string sc = "star-count --runs 31 --seed 7 --no-plots";
  ASSERT_EQ(mc(sc + " --out " + whole), 0);
  ASSERT_EQ(mc(sc + " --shard 0/2 --out " + s0), 0);
  ASSERT_EQ(mc(sc + " --shard 1/2 --out " + s1), 0);
  ASSERT_EQ(mc("merge " + s0 + " " + s1 + " --no-plots --out " + merged), 0);
  expectSameFiles(whole, merged,
                  {"star-count_trials.csv", "star-count_per_mag.csv", "star-count_histogram.csv",
                   "star-count.md"});
  // Teeth: shards of runs with different options are refused.
  const std::string s2 = test::makeTempDir("mc_s2");
  ASSERT_EQ(mc("star-count --runs 31 --seed 8 --no-plots --shard 1/2 --out " + s2), 0);
  EXPECT_EQ(mc("merge " + s0 + " " + s2 + " --no-plots --out " + merged, &out), 2);
  EXPECT_NE(out.find("different options"), std::string::npos) << out;
}

TEST(Montecarlo, ThreadCountDoesNotChangeResults) {
  const std::string t1 = test::makeTempDir("mc_t1"), t2 = test::makeTempDir("mc_t2"),
                    t3 = test::makeTempDir("mc_t3");
  const std::string common = "lis-robustness --runs 6 --algorithms pyramid,planar --no-plots";
  ASSERT_EQ(mc(common + " --threads 1 --out " + t1), 0);
  ASSERT_EQ(mc(common + " --threads 2 --out " + t2), 0);
  expectSameFiles(t1, t2, {"lis-robustness_trials.csv", "lis-robustness_situations.csv"});
  // Teeth: the comparison can fail: another seed gives other trials.
  ASSERT_EQ(mc(common + " --threads 2 --seed 2 --out " + t3), 0);
  EXPECT_NE(readFile(t1 + "/lis-robustness_trials.csv"),
            readFile(t3 + "/lis-robustness_trials.csv"));
}

TEST(Montecarlo, BadInputExitsTwoWithAClearMessage) {
  const std::string dir = test::makeTempDir("mc_bad");
  std::string out;
  EXPECT_EQ(mc("no-such-experiment --out " + dir, &out), 2);
  EXPECT_NE(out.find("unknown experiment 'no-such-experiment'"), std::string::npos) << out;
  EXPECT_NE(out.find("lis-robustness"), std::string::npos) << out;  // lists the valid names
  for (const char* shard : {"2/2", "x", "1/0", "-1/3", "1/2/3"}) {
    EXPECT_EQ(mc(std::string("star-count --runs 2 --shard ") + shard + " --out " + dir, &out), 2) << shard;
    EXPECT_NE(out.find("--shard '" + std::string(shard) + "'"), std::string::npos) << out;
  }
  EXPECT_EQ(mc("lis-robustness --runs 2 --algorithms pyramid,nope --out " + dir, &out), 2);
  EXPECT_NE(out.find("nope"), std::string::npos) << out;
  EXPECT_EQ(mc("merge " + dir + "/missing-dir --out " + dir, &out), 2);
  EXPECT_NE(out.find("not a directory"), std::string::npos) << out;
}

TEST(Montecarlo, MissingGnuplotIsAClearErrorAfterTheTables) {
  const std::string dir = test::makeTempDir("mc_nognuplot");
  std::string out;
  const int rc = test::runCommand(test::startrackerExe() + " montecarlo star-count --runs 5 -q "
                                  "--gnuplot /nonexistent/gnuplot --out " + dir, &out);
  EXPECT_EQ(rc, 1) << out;
  EXPECT_NE(out.find("gnuplot not found"), std::string::npos) << out;
  EXPECT_NE(out.find("gnuplot-nox"), std::string::npos) << out;
  EXPECT_TRUE(fs::exists(dir + "/star-count_per_mag.csv"));
  EXPECT_TRUE(fs::exists(dir + "/star-count.md"));
}

}  // namespace
}  // namespace st
