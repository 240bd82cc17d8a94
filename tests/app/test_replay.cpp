// End-to-end: `startracker replay` on the committed sample rawlogs (rawlogs/*.rawlog, made by
// `startracker simulate rawlogs/<name>.ini`), and its handling of bad input.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "sensors/mrpt/rawlog_io.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

namespace fs = std::filesystem;

std::string sample(const std::string& name) {
  return test::repoDir() + "/rawlogs/" + name + ".rawlog";
}

double grab(const std::string& out, const std::string& pattern) {
  std::smatch m;
  if (!std::regex_search(out, m, std::regex(pattern))) return -1;
  return std::stod(m[1]);
}

std::size_t lines(const std::string& path) {
  std::ifstream f(path);
  std::size_t n = 0;
  for (std::string l; std::getline(f, l);) ++n;
  return n;
}

struct SampleCase {
  std::string name;
  int frames;          // CAMERA frames in the rawlog
  double solved_pct;   // expected
  bool tracker_ini;    // --config rawlogs/tracker.ini (the samples' detector, as demo.sh)
};

class ReplaySample : public ::testing::TestWithParam<SampleCase> {};

// Error bound from the simulation's noise (rawlogs/*.ini: 512 px over 15 deg = 105.5 arcsec/px,
// PSF sigma 1 px, stars of SNR >= ~20): a centroid's 1-sigma is <= 0.1 px, and a fix uses
// n >= 10 stars spread over r_rms ~ 180 px from the boresight. Per axis, cross-boresight
// sigma <= 0.1 * 105.5 / sqrt(10) = 3.3 arcsec, i.e. <= 4.7 arcsec for the two axes together;
// roll sigma <= 0.1 / (180 sqrt(10)) rad = 36 arcsec. The filter only reduces these, so the
// RMS over a run must stay below 3 sigma of the worst case: 14 arcsec cross-boresight and
// 110 arcsec roll.
TEST_P(ReplaySample, SolvesTracksAndWritesOutputs) {
  const SampleCase c = GetParam();
  const std::string dir = test::makeTempDir("replay_" + c.name);
  const std::string out_rawlog = dir + "/out.rawlog", csv = dir + "/traj.csv";
  const std::string config =
      c.tracker_ini ? " --config " + test::repoDir() + "/rawlogs/tracker.ini" : "";
  std::string out;
  const int rc = test::runCommand(test::startrackerExe() + " replay -q " + sample(c.name) +
                                      config + " -o " + out_rawlog + " --csv " + csv +
                                      " --plots " + dir + "/plots",
                                  &out);
  ASSERT_EQ(rc, 0) << out;
  EXPECT_EQ(grab(out, R"(frames: (\d+))"), c.frames) << out;
  EXPECT_NEAR(grab(out, R"(solved ([0-9.]+) %)"), c.solved_pct, 1e-9) << out;
  EXPECT_EQ(grab(out, R"(lost-in-space (\d+))"), 1) << out;
  const double cross = grab(out, R"(cross-boresight\s+RMS\s+([0-9.]+))");
  const double roll = grab(out, R"(roll\s+RMS\s+([0-9.]+))");
  EXPECT_GE(cross, 0) << out;
  EXPECT_LT(cross, 14.0) << out;
  EXPECT_GE(roll, 0) << out;
  EXPECT_LT(roll, 110.0) << out;
  EXPECT_EQ(grab(out, R"(, (\d+) misidentified)"), 0) << out;

  // CSV: header + one row per frame.
  EXPECT_EQ(lines(csv), std::size_t(c.frames) + 1);
  // Output rawlog: every input object plus one STAR_TRACKER per frame, readable.
  const std::size_t in_count = readRawlog(sample(c.name)).size();
  const auto objs = readRawlog(out_rawlog);
  EXPECT_EQ(objs.size(), in_count + std::size_t(c.frames));
  EXPECT_EQ(std::count_if(objs.begin(), objs.end(),
                          [](const auto& o) { return o->sensorLabel == "STAR_TRACKER"; }),
            c.frames);
  // The external images resolve from the output's folder.
  EXPECT_TRUE(fs::exists(rawlogImagesDir(out_rawlog) + "/CAMERA_000000.png"));
  if (out.find("not drawn") == std::string::npos) {
    for (const char* p : {"error", "nees", "bias", "stars", "frame_time"})
      EXPECT_TRUE(fs::exists(dir + "/plots/" + p + ".png")) << p;
  }
}

INSTANTIATE_TEST_SUITE_P(Samples, ReplaySample,
                         ::testing::Values(SampleCase{"slew_2dps", 12, 100.0, false},
                                           SampleCase{"hold", 12, 100.0, false},
                                           SampleCase{"faults_dropout", 15, 100.0, false},
                                           SampleCase{"slew_2dps", 12, 100.0, true},
                                           SampleCase{"hold", 12, 100.0, true},
                                           SampleCase{"faults_dropout", 15, 100.0, true}),
                         [](const auto& info) {
                           return info.param.name + (info.param.tracker_ini ? "_tracker_ini" : "");
                         });

// ---- bad input: a message naming the file and the problem, exit 1 or 2, no crash --------

void expectCleanFailure(const std::string& args, const std::string& must_name) {
  std::string out;
  const int rc = test::runCommand(test::startrackerExe() + " replay -q " + args, &out);
  EXPECT_TRUE(rc == 1 || rc == 2) << "exit " << rc << "\n" << out;
  EXPECT_NE(out.find(must_name), std::string::npos) << out;
}

TEST(ReplayBadInput, MissingTruncatedNonRawlogBadIniBadDatabase) {
  const std::string dir = test::makeTempDir("replay_bad");
  expectCleanFailure(dir + "/nope.rawlog", "nope.rawlog");

  // Truncated: the first half of a gz rawlog.
  {
    std::ifstream in(sample("hold"), std::ios::binary);
    const std::string all((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(dir + "/cut.rawlog", std::ios::binary) << all.substr(0, all.size() / 2);
  }
  expectCleanFailure(dir + "/cut.rawlog", "cut.rawlog");

  std::ofstream(dir + "/text.rawlog") << "this is not a rawlog\n";
  expectCleanFailure(dir + "/text.rawlog", "text.rawlog");

  std::ofstream(dir + "/bad.ini") << "[pipeline]\ngain_e_per_adu_typo = 8\n";
  expectCleanFailure(sample("hold") + " --config " + dir + "/bad.ini", "gain_e_per_adu_typo");

  std::ofstream(dir + "/old.db") << "STDB but not a database of this version";
  std::ofstream(dir + "/db.ini") << "[database]\npath = old.db\n";
  expectCleanFailure(sample("hold") + " --config " + dir + "/db.ini", "old.db");
}

}  // namespace
}  // namespace st
