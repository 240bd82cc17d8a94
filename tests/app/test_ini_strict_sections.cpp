// Issue 39, "silently wrong": a misspelt section used to be ignored in every .ini (keys were
// strict, sections not): `[pipelin]` in a tracker file replayed with default exposure and
// noise, `[gyr]` in a scenario simulated no gyro, `[navigatr]` in a live .ini was ignored; a
// scenario given to `replay --config` was accepted; a key written twice kept the last in
// silence. Each is now refused by the real program, naming the file, section or key, exit 2.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "tests/app/test_cli_run.hpp"

namespace st {
namespace {

/// `file` of the repository's rawlogs/ with its first `from` replaced by `to`, as dir/name.
std::string edited(const std::string& dir, const std::string& file, const std::string& from,
                   const std::string& to, const std::string& name) {
  std::string s = test::fileBytes(test::repoDir() + "/rawlogs/" + file);
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from << " not in " << file;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  std::ofstream(dir + "/" + name) << s;
  return name;
}

void expectUsageError(const test::CliRun& r, const std::string& what) {
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_THAT(r.err, ::testing::HasSubstr(what));
}

std::string hold() { return "'" + test::repoDir() + "/rawlogs/hold.rawlog'"; }

TEST(IniStrictSections, MisspeltTrackerSectionIsRefusedWithTheNearestOne) {
  const std::string dir = test::makeTempDir("ini_tracker_section");
  const std::string ini = edited(dir, "tracker.ini", "[pipeline]", "[pipelin]", "t.ini");
  expectUsageError(test::runCli("replay " + hold() + " --config " + ini, dir),
                   "t.ini: [pipelin]: unknown section; did you mean [pipeline]?");
  expectUsageError(test::runCli("config " + ini, dir), "[pipelin]: unknown section");
}

TEST(IniStrictSections, MisspeltScenarioSectionIsRefusedNotReadAsAbsent) {
  const std::string dir = test::makeTempDir("ini_scenario_section");
  const std::string gyr = edited(dir, "hold.ini", "[gyro]", "[gyr]", "gyr.ini");
  expectUsageError(test::runCli("simulate " + gyr + " -o s.rawlog --frames 2", dir),
                   "gyr.ini: [gyr]: unknown section; did you mean [gyro]?");
  // A required section misspelt: the missing one is named with the likely misspelling.
  const std::string camer = edited(dir, "hold.ini", "[camera]", "[camer]", "camer.ini");
  expectUsageError(test::runCli("simulate " + camer + " -o s.rawlog --frames 2", dir),
                   "[camera]: missing section (is [camer] a misspelling of it?)");
}

TEST(IniStrictSections, MisspeltLiveSectionIsRefused) {
  const std::string dir = test::makeTempDir("ini_live_section");
  const std::string ini = edited(dir, "live_sim.ini", "[navigator]", "[navigatr]", "l.ini");
  expectUsageError(test::runCli("config " + ini, dir),
                   "[navigatr]: unknown section; did you mean [navigator]?");
}

TEST(IniStrictSections, AFileOfAnotherSchemaIsRefusedByWhatItContains) {
  const std::string dir = test::makeTempDir("ini_kind");
  const std::string scenario = test::repoDir() + "/rawlogs/hold.ini";
  expectUsageError(test::runCli("replay " + hold() + " --config '" + scenario + "'", dir),
                   "this is a scenario file; replay --config takes a tracker file");
  const std::string tracker = test::repoDir() + "/rawlogs/tracker.ini";
  expectUsageError(test::runCli("simulate '" + tracker + "' -o s.rawlog --frames 2", dir),
                   "this is a tracker file; a scenario file has a [scenario] section");
}

TEST(IniStrictSections, AKeyWrittenTwiceIsRefusedNamingTheLine) {
  const std::string dir = test::makeTempDir("ini_duplicate_key");
  std::ofstream(dir + "/d.ini") << "[filter]\ngyro_noise_deg_s = 0.1\n; a comment\n"
                                   "gyro_noise_deg_s = 0.2\n";
  expectUsageError(test::runCli("replay " + hold() + " --config d.ini", dir),
                   "d.ini:4: [filter] key 'gyro_noise_deg_s' is written twice");
  // The same key in two sections is two keys.
  std::ofstream(dir + "/two.ini") << "[filter]\nmodel = gyro\n[pipeline]\nmodel = x\n";
  const test::CliRun r = test::runCli("config two.ini", dir);
  EXPECT_THAT(r.err, ::testing::Not(::testing::HasSubstr("written twice")));
}

TEST(IniStrictSections, MontecarloRunFileKnowsOneSection) {
  const std::string dir = test::makeTempDir("ini_mc_section");
  std::ofstream(dir + "/r.txt") << test::fileBytes(test::repoDir() +
                                          "/docs/montecarlo/centroid-defocus/centroid-defocus_run.txt")
                                << "\n[montecarlo_rn]\nruns = 3\n";
  expectUsageError(test::runCli("config r.txt", dir),
                   "[montecarlo_rn]: unknown section; did you mean [montecarlo_run]?");
}

}  // namespace
}  // namespace st
