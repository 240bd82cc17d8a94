// The seed experiments beside the papers' numbers (issue 17 item 2, docs/montecarlo/seed00*.md):
// a small seeded run of each in the seed's own configuration, with another seed than the
// full-size run, must land within the statistical tolerance (3 sigma: binomial for a
// fraction, the sample's own standard error for a mean or RMS) of the paper's number, or of
// our full-size number where the two differ for a reason the docs explain. Each pin fails
// with a wrong configuration (checked by hand, see the lead's report): e.g. the rectangle
// instead of seed 003's 30 deg circle, one head instead of two, psfWidth read as the FWHM.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "tests/support/csv_file.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

using Csv = std::vector<std::vector<std::string>>;  // header first

std::string runMc(const std::string& args) {
  const std::string dir = test::makeTempDir("mc_seeds");
  std::string out;
  const int rc = test::runCommand(test::startrackerExe() + " montecarlo " + args +
                                      " --no-plots -q --out " + dir, &out);
  EXPECT_EQ(rc, 0) << args << "\n" << out;
  return dir;
}

std::size_t column(const Csv& t, const std::string& name) {
  const auto it = std::find(t.at(0).begin(), t.at(0).end(), name);
  EXPECT_NE(it, t.at(0).end()) << "no column " << name;
  return static_cast<std::size_t>(it - t.at(0).begin());
}

double num(const std::string& s) { return std::strtod(s.c_str(), nullptr); }

// The row of `t` whose first cells equal `key` (in order).
const std::vector<std::string>& row(const Csv& t, const std::vector<std::string>& key) {
  for (std::size_t i = 1; i < t.size(); ++i)
    if (std::equal(key.begin(), key.end(), t[i].begin())) return t[i];
  ADD_FAILURE() << "no row " << key.front();
  static const std::vector<std::string> empty(20, "nan");
  return empty;
}

double binomialSigma(double p, double n) { return std::sqrt(p * (1 - p) / n); }

// Seed 000 Fig. 1: 32 x 32 deg, V <= 3, NT = 1000 random attitudes. The seed's text gives
// no number; issue 17's 72 % (>= 3 stars) and 50.6 % (>= 4) are our own 1000-attitude run
// with seed 1, so the pin is our 10,000-attitude run (seed 1): 70.75 % and 51.74 %, and the
// tolerance combines the binomial sigmas of both runs.
TEST(SeedTables, Seed000Fig1StarsInTheReferenceCamera) {
  const std::string dir = runMc("star-count --runs 1000 --seed 2 --fov-deg 32 --mag-limit 3 --mags 3");
  const Csv per = test::readCsvCells(dir + "/star-count_per_mag.csv");
  const auto& r = row(per, {"3"});
  const double ge3 = 1 - num(r[column(per, "P(N<3)")]), ge4 = 1 - num(r[column(per, "P(N<4)")]);
  auto tol = [](double p) { return 3 * std::sqrt(p * (1 - p) * (1 / 1000.0 + 1 / 10000.0)); };
  EXPECT_NEAR(ge3, 0.7075, tol(0.7075));
  EXPECT_NEAR(ge4, 0.5174, tol(0.5174));
}

// Seed 003 Fig. 2: a 30 deg opening angle sees 18.9 stars brighter than "optical class 4.5"
// on average (10,000 simulations) = its 1107 stars x the cone's (1 - cos 15 deg) / 2 of the
// sky. Our catalog holds 1104 stars at V <= 4.67 (922 at V <= 4.5: 15.71 expected).
TEST(SeedTables, Seed003Fig2MeanStarsInTheOpeningAngle) {
  const double n = 2000;
  const std::string dir = runMc("star-count --runs 2000 --seed 2 --fov-deg 30 --size 576 604 "
                                "--field-stop-deg 30 --mags 4.5,4.67 --mag-limit 4.5");
  const Csv per = test::readCsvCells(dir + "/star-count_per_mag.csv");
  const std::size_t c_mean = column(per, "mean"), c_std = column(per, "std");
  const auto& r467 = row(per, {"4.67"});
  const double sd = num(r467[c_std]);
  // Both means carry sampling noise: ours over n trials, the paper's over 10,000.
  EXPECT_NEAR(num(r467[c_mean]), 18.9, 3 * sd * std::sqrt(1 / n + 1 / 10000.0));
  const double cone = (1 - std::cos(15.0 * M_PI / 180)) / 2;
  const auto& r45 = row(per, {"4.5"});
  EXPECT_NEAR(num(r45[c_mean]), 922 * cone, 3 * num(r45[c_std]) / std::sqrt(n));
}

// Seed 003 Tables 2-3 in the seed's camera (576 x 604 px, 30 deg circle, V <= 4.5, 1/5 px):
// the Liebe identification (the seed's IE) with all stars in tolerance, and the accuracy of
// the optical axis (paper: 14.6" RMS). Full size (500 trials, seed 1): 98.2 % correct, 15.14".
TEST(SeedTables, Seed003Tables2And3LiebeInTheSeedsCamera) {
  const std::string dir = runMc("lis-robustness --runs 200 --seed 2 --fov-deg 30 --size 576 604 "
                                "--field-stop-deg 30 --mag-limit 4.5 --noise-px 0.2 "
                                "--algorithms liebe");
  const Csv trials = test::readCsvCells(dir + "/lis-robustness_trials.csv");
  const std::size_t c_sit = column(trials, "situation"), c_ok = column(trials, "solved"),
                    c_false = column(trials, "false_id"),
                    c_cross = column(trials, "err_cross_arcsec");
  double n = 0, ok = 0, wrong = 0;
  std::vector<double> e2;
  for (std::size_t i = 1; i < trials.size(); ++i) {
    wrong += trials[i][c_false] == "1";
    if (trials[i][c_sit] != "all stars in tolerance") continue;
    ++n;
    if (trials[i][c_ok] != "1") continue;
    ++ok;
    e2.push_back(std::pow(num(trials[i][c_cross]), 2));
  }
  ASSERT_EQ(n, 200);
  EXPECT_EQ(wrong, 0);
  EXPECT_NEAR(ok / n, 0.982, 3 * binomialSigma(0.982, n));
  // RMS of the cross-boresight error and its standard error from the sample itself.
  double m = 0, v = 0;
  for (double x : e2) m += x / double(e2.size());
  for (double x : e2) v += (x - m) * (x - m) / double(e2.size() - 1);
  const double rms = std::sqrt(m), se = std::sqrt(v / double(e2.size())) / (2 * rms);
  EXPECT_NEAR(rms, 14.6, 3 * se) << "standard error " << se;
}

// Seed 002 Fig. 11's second curve: two identical heads (boresights 90 deg apart), V <= 5,
// 8 deg square FOV. Full size (1000 trials, seed 1): P(N < 3) = 0.151, P(N < 4) = 0.297
// (one head: 0.601, 0.773).
TEST(SeedTables, Seed002Fig11TwoHeads) {
  const std::string dir = runMc("fov-selection --runs 1000 --seed 2 --heads 2 --fovs 8 --mags 5");
  const Csv p = test::readCsvCells(dir + "/fov-selection_probabilities.csv");
  const auto& r = row(p, {"2", "5", "8"});  // heads, V_limit, fov_deg
  EXPECT_NEAR(num(r[column(p, "P(N<3)")]), 0.151, 3 * binomialSigma(0.151, 1000));
  EXPECT_NEAR(num(r[column(p, "P(N<4)")]), 0.297, 3 * binomialSigma(0.297, 1000));
  // The first head alone, from the same attitudes: the one-head curve.
  const auto& r1 = row(p, {"1", "5", "8"});
  EXPECT_NEAR(num(r1[column(p, "P(N<3)")]), 0.601, 3 * binomialSigma(0.601, 1000));
}

// Seed 004 Table 5.1 says a 30 deg FOV always holds >= 4 stars at V <= 3.6 and >= 6 at
// V <= 3.9; a 30 deg square does not (holes: the docs explain). Full size (20,000 trials,
// seed 1): P(N >= 4 | V 3.6) = 0.8142. The required-magnitude table (the smallest limit
// whose minimum over the trials reaches N) is recomputed from the per-limit minima; the
// limits are chosen so that some minimum equals some N (checked), where ">=" matters.
TEST(SeedTables, Seed004Table5_1StarsAtTheSeedsMagnitudes) {
  const double n = 4000;
  const std::string dir = runMc("star-count --runs 4000 --seed 2 --fov-deg 30 "
                                "--mags 3.6,3.9,4.3,4.4,4.5,4.6,4.7,4.8,4.9,5 --mag-limit 3.6");
  const Csv per = test::readCsvCells(dir + "/star-count_per_mag.csv");
  const auto& r = row(per, {"3.6"});
  EXPECT_NEAR(1 - num(r[column(per, "P(N<4)")]), 0.8142, 3 * binomialSigma(0.8142, n));
  const Csv req = test::readCsvCells(dir + "/star-count_required_mag.csv");
  ASSERT_EQ(req.size(), 6u);  // header + N = 3, 4, 5, 6, 8
  const std::size_t c_min = column(per, "min");
  bool boundary = false;
  for (std::size_t k = 1; k < req.size(); ++k) {
    const int n_min = std::stoi(req[k][0]);
    std::string want = "> grid";
    for (std::size_t i = 1; i < per.size(); ++i) {
      boundary = boundary || num(per[i][c_min]) == n_min;
      if (num(per[i][c_min]) >= n_min) {
        want = per[i][0];
        break;
      }
    }
    EXPECT_EQ(req[k][1], want) << "N = " << n_min;
  }
  EXPECT_TRUE(boundary) << "no minimum equals any N: the test would not see > for >=";
}

// Seed 004 sec. 5.5.4: SKY2000 V < 6 has 5060 stars; keeping the 8 brightest of every field
// leaves 540. Ours (Hipparcos, doubles within 60" merged): 5025, and 591 with cones of half
// the pair angle (19.04 deg) of the seed's 30 x 24.25 deg camera. Deterministic: exact.
TEST(SeedTables, Seed004ReducedCatalog) {
  const std::string dir = test::makeTempDir("mc_seeds_reduced");
  std::string out;
  ASSERT_EQ(test::runCommand(test::startrackerExe() +
                                 " catalog build --fov-deg 30 --size 1280 1024 --mag-limit 6 "
                                 "--per-region 8 --epoch 2000 --double-star-arcsec 60 "
                                 "--no-aberration --no-parallax -q -o " + dir + "/r.db", &out),
            0)
      << out;
  ASSERT_EQ(test::runCommand(test::startrackerExe() + " catalog info " + dir + "/r.db", &out), 0)
      << out;
  EXPECT_NE(out.find("after mag limit      5025"), std::string::npos) << out;
  EXPECT_NE(out.find("after density        591"), std::string::npos) << out;
}

// Seed 004 Table 5.3 in the camera of its Table 5.2: measured minus assigned magnitude of 20
// stars per image. The maximum-likelihood flux is unbiased (theory: mean 0 within 3 standard
// errors at every V); the weighted sum loses the faint wings (full size, 500 stars: +0.101 at
// V = 4, std 0.048; paper +0.136, std 0.069). Every star up to V = 3 is found.
TEST(SeedTables, Seed004Table5_3MagnitudeError) {
  const std::string dir = runMc("magnitude-error --runs 5 --seed 2 --size 1280 1024");
  const Csv t = test::readCsvCells(dir + "/magnitude-error_table5_3.csv");
  const std::size_t c_n = column(t, "stars"), c_mean = column(t, "mean_diff"),
                    c_sd = column(t, "std_diff"), c_all = column(t, "images_all_found");
  for (const char* v : {"0", "1", "2", "3"}) {
    SCOPED_TRACE(v);
    for (const char* c : {"cog", "gauss"}) EXPECT_EQ(row(t, {v, c})[c_all], "5") << c;
    const auto& g = row(t, {v, "gauss"});
    EXPECT_NEAR(num(g[c_mean]), 0, 3 * num(g[c_sd]) / std::sqrt(num(g[c_n])));
  }
  const auto& w4 = row(t, {"4", "cog"});
  EXPECT_NEAR(num(w4[c_mean]), 0.101, 3 * 0.048 / std::sqrt(num(w4[c_n])));
}

// The new options are refused where an experiment cannot honour them (exit 2, named).
TEST(SeedTables, OptionsAnExperimentCannotHonourAreRefused) {
  std::string out;
  const std::string mc = test::startrackerExe() + " montecarlo ";
  EXPECT_EQ(test::runCommand(mc + "star-count --runs 2 --heads 2 --no-plots -q --out " +
                                 test::makeTempDir("mc_seeds_bad"), &out), 2);
  EXPECT_NE(out.find("--heads 2"), std::string::npos) << out;
  EXPECT_EQ(test::runCommand(mc + "fov-selection --runs 2 --field-stop-deg 10 --no-plots -q --out " +
                                 test::makeTempDir("mc_seeds_bad"), &out), 2);
  EXPECT_NE(out.find("--field-stop-deg 10"), std::string::npos) << out;
  EXPECT_EQ(test::runCommand(mc + "fov-selection --runs 2 --heads 4 --no-plots -q --out " +
                                 test::makeTempDir("mc_seeds_bad"), &out), 2);
}

}  // namespace
}  // namespace st
