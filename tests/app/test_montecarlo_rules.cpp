// Teeth for the Monte Carlo tables (issue 17 item 1): every value of the star-count and
// fov-selection summary tables is recomputed here from the raw trial table the same run
// wrote (one star count per trial and FOV), by the definitions the tables claim:
// P(N < 3) counts the trials with 0, 1 or 2 stars, P(N < 4) those with at most 3, and the
// FOV "needed" is the smallest one with P < 0.01 (seed 002 eq. 14). The runs are chosen so
// that trials with exactly 3 and exactly 4 stars occur (checked), so a boundary moved by one
// (N < 3 -> N <= 3) changes the tables and fails here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/csv_file.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

using Csv = std::vector<std::vector<std::string>>;  // header first

Csv readCsv(const std::string& path) {
  EXPECT_TRUE(std::ifstream(path).good()) << path;
  return test::readCsvCells(path);
}

std::size_t column(const Csv& t, const std::string& name) {
  const auto it = std::find(t.at(0).begin(), t.at(0).end(), name);
  EXPECT_NE(it, t.at(0).end()) << "no column " << name;
  return static_cast<std::size_t>(it - t.at(0).begin());
}

double num(const std::string& s) { return std::strtod(s.c_str(), nullptr); }

// The tables print 4 significant digits (%.4g) and the CI 3.
void expectValue(const std::string& cell, double want, const std::string& what) {
  EXPECT_NEAR(num(cell), want, 1e-12 + 5e-4 * std::abs(want)) << what << ": table " << cell;
}

std::string run(const std::string& args) {
  const std::string dir = test::makeTempDir("mc_rules");
  std::string out;
  const int rc = test::runCommand(test::startrackerExe() + " montecarlo " + args +
                                      " --no-plots -q --out " + dir, &out);
  EXPECT_EQ(rc, 0) << out;
  return dir;
}

// 8 deg, V <= 4 .. 5: 0 to ~15 stars per image, so every count near the boundaries occurs.
TEST(MontecarloTables, StarCountTableFollowsItsTrials) {
  const std::string dir = run("star-count --runs 400 --seed 3 --fov-deg 8 --mags 4,4.5,5 --mag-limit 4.5");
  const Csv trials = readCsv(dir + "/star-count_trials.csv");
  const Csv per = readCsv(dir + "/star-count_per_mag.csv");
  ASSERT_EQ(trials.size(), 401u);
  ASSERT_EQ(per.size(), 4u);  // header + 3 limits
  std::map<int, int> seen;    // count -> trials, over every limit
  for (std::size_t r = 1; r < per.size(); ++r) {
    const std::string v = per[r][column(per, "V_limit")];
    const std::size_t c = column(trials, "n_V" + v);
    std::vector<int> n;
    for (std::size_t k = 1; k < trials.size(); ++k) n.push_back(std::atoi(trials[k][c].c_str()));
    for (int x : n) ++seen[x];
    const double total = static_cast<double>(n.size());
    double sum = 0;
    int lt3 = 0, lt4 = 0;
    for (int x : n) {
      sum += x;
      lt3 += x <= 2;
      lt4 += x <= 3;
    }
    SCOPED_TRACE("V <= " + v);
    EXPECT_EQ(per[r][column(per, "trials")], std::to_string(n.size()));
    expectValue(per[r][column(per, "mean")], sum / total, "mean");
    expectValue(per[r][column(per, "min")], *std::min_element(n.begin(), n.end()), "min");
    expectValue(per[r][column(per, "max")], *std::max_element(n.begin(), n.end()), "max");
    expectValue(per[r][column(per, "P(N<3)")], lt3 / total, "P(N<3)");
    expectValue(per[r][column(per, "P(N<4)")], lt4 / total, "P(N<4)");
  }
  // The boundaries are exercised: images with exactly 2, 3 and 4 stars.
  EXPECT_GT(seen[2], 10);
  EXPECT_GT(seen[3], 10);
  EXPECT_GT(seen[4], 10);

  // The histogram at --mag-limit: trials and cumulative fraction per count.
  const Csv hist = readCsv(dir + "/star-count_histogram.csv");
  const std::size_t c = column(trials, "n_V4.5");
  std::map<int, int> h;
  for (std::size_t k = 1; k < trials.size(); ++k) ++h[std::atoi(trials[k][c].c_str())];
  int cum = 0;
  for (std::size_t r = 1; r < hist.size(); ++r) {
    const int stars = std::atoi(hist[r][column(hist, "stars")].c_str());
    cum += h[stars];
    EXPECT_EQ(std::atoi(hist[r][column(hist, "trials")].c_str()), h[stars]) << stars << " stars";
    expectValue(hist[r][column(hist, "cumulative")], cum / 400.0, "cumulative");
  }
}

TEST(MontecarloTables, FovSelectionTableFollowsItsTrials) {
  const std::string dir =
      run("fov-selection --runs 300 --seed 5 --mags 4.5,5 --fovs 10,12,14,15,16,17,18,19,20,22,24,26,28");
  const Csv trials = readCsv(dir + "/fov-selection_trials.csv");
  const Csv prob = readCsv(dir + "/fov-selection_probabilities.csv");
  const Csv need = readCsv(dir + "/fov-selection_fov_needed.csv");
  ASSERT_EQ(trials.size(), 601u);  // one row per trial and limit
  int exactly3 = 0, exactly4 = 0;
  std::map<std::string, std::pair<std::string, std::string>> first_below;  // per V: FOV for N<3, N<4
  for (std::size_t r = 1; r < prob.size(); ++r) {
    const std::string v = prob[r][column(prob, "V_limit")], f = prob[r][column(prob, "fov_deg")];
    const std::size_t c = column(trials, "n_fov" + f);
    int n = 0, lt3 = 0, lt4 = 0;
    double sum = 0;
    for (std::size_t k = 1; k < trials.size(); ++k) {
      if (trials[k][column(trials, "V_limit")] != v) continue;
      const int x = std::atoi(trials[k][c].c_str());
      ++n;
      sum += x;
      lt3 += x <= 2;
      lt4 += x <= 3;
      exactly3 += x == 3;
      exactly4 += x == 4;
    }
    SCOPED_TRACE("V <= " + v + ", FOV " + f);
    EXPECT_EQ(prob[r][column(prob, "trials")], std::to_string(n));
    expectValue(prob[r][column(prob, "mean_N")], sum / n, "mean_N");
    expectValue(prob[r][column(prob, "P(N<3)")], double(lt3) / n, "P(N<3)");
    expectValue(prob[r][column(prob, "P(N<4)")], double(lt4) / n, "P(N<4)");
    auto& fb = first_below[v];
    if (fb.first.empty() && double(lt3) / n < 0.01) fb.first = f;
    if (fb.second.empty() && double(lt4) / n < 0.01) fb.second = f;
  }
  EXPECT_GT(exactly3, 10);
  EXPECT_GT(exactly4, 10);
  ASSERT_EQ(need.size(), 3u);
  for (std::size_t r = 1; r < need.size(); ++r) {
    const std::string v = need[r][0];
    SCOPED_TRACE("V <= " + v);
    const auto& fb = first_below[v];
    EXPECT_EQ(need[r][1], fb.first.empty() ? "> grid" : fb.first);
    EXPECT_EQ(need[r][2], fb.second.empty() ? "> grid" : fb.second);
  }
}

}  // namespace
}  // namespace st
