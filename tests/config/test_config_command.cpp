// `startracker config` and the strict schemas end to end: for each schema (scenario, camera,
// simulated sensors, montecarlo run file, tracker.ini, the live .ini's own sections, the
// CStarTrackerSensor section and its tracker keys), a misspelled key
// in a temporary file makes the real executable exit 2 with a message naming the file, the
// section, the key and the nearest valid key; every sample .ini prints an effective
// configuration that reads back to the same configuration.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "tests/support/test_paths.hpp"

namespace st {
namespace {
namespace fs = std::filesystem;

std::string exe() { return test::startrackerExe(); }

std::string readText(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

/// The sample with one line replaced (`from` must occur in it).
std::string withTypo(const std::string& text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  if (pos == std::string::npos) return text;
  return text.substr(0, pos) + to + text.substr(pos + from.size());
}

void expectTypoMessage(const std::string& out, const std::string& file, const std::string& section,
                       const std::string& key, const std::string& suggestion) {
  EXPECT_NE(out.find(file), std::string::npos) << out;
  // "[S] key 'K'" or, through MRPT's sensor loader, "section 'S' key 'K'".
  EXPECT_TRUE(out.find("[" + section + "] key '" + key + "'") != std::string::npos ||
              out.find("section '" + section + "' key '" + key + "'") != std::string::npos)
      << out;
  EXPECT_NE(out.find("did you mean '" + suggestion + "'?"), std::string::npos) << out;
}

struct Typo {
  std::string section, from, to, key, suggestion;
};

TEST(ConfigCommand, ScenarioTyposFailInEverySection) {
  const std::string dir = test::makeTempDir("cfg_scenario");
  const std::string sample = readText(test::repoDir() + "/rawlogs/slew_2dps.ini");
  const std::vector<Typo> typos = {
      {"scenario", "frame_rate_hz  =", "frame_rate_hzz =", "frame_rate_hzz", "frame_rate_hz"},
      {"camera", "fov_deg    =", "fov_dg     =", "fov_dg", "fov_deg"},
      {"sensor", "qe                   =", "qee                  =", "qee", "qe"},
      {"motion", "rate_deg_s =", "rate_dg_s  =", "rate_dg_s", "rate_deg_s"},
      {"gyro", "arw_deg_rt_h       =", "arw_deg_rth        =", "arw_deg_rth", "arw_deg_rt_h"},
      {"faults", "[faults]\n", "[faults]\nspikes_per_frme = 1\n", "spikes_per_frme", "spikes_per_frame"},
  };
  for (const Typo& t : typos) {
    SCOPED_TRACE(t.key);
    const std::string path = dir + "/typo_" + t.section + ".ini";
    std::ofstream(path) << withTypo(sample, t.from, t.to);
    std::string out;
    EXPECT_EQ(test::runCommand(exe() + " config " + path, &out), 2) << out;
    expectTypoMessage(out, path, t.section, t.key, t.suggestion);
    // The command that uses the file refuses it the same way, before any work.
    EXPECT_EQ(test::runCommand(exe() + " simulate " + path + " -o " + dir + "/x.rawlog -q", &out), 2)
        << out;
    expectTypoMessage(out, path, t.section, t.key, t.suggestion);
  }
}

TEST(ConfigCommand, CameraIniTypo) {
  const std::string dir = test::makeTempDir("cfg_camera");
  const std::string good = "[CAMERA]\nresolution = [640 480]\ncx = 319.5\ncy = 239.5\nfx = 800\nfy = 800\n";
  std::ofstream(dir + "/good.ini") << good;
  std::string out;
  ASSERT_EQ(test::runCommand(exe() + " config " + dir + "/good.ini", &out), 0) << out;
  EXPECT_NE(out.find("[CAMERA]"), std::string::npos) << out;
  EXPECT_NE(out.find("dist = [0 0 0 0 0]"), std::string::npos) << out;  // a default filled in
  const std::string path = dir + "/typo.ini";
  std::ofstream(path) << withTypo(good, "cy =", "cyy =");
  for (const std::string& cmd : {" config " + path,
                                 " camera --camera " + path + " --camera-section CAMERA"}) {
    EXPECT_EQ(test::runCommand(exe() + cmd, &out), 2) << out;
    expectTypoMessage(out, path, "CAMERA", "cyy", "cy");
  }
}

TEST(ConfigCommand, SimulatedSensorSectionTypo) {
  const std::string dir = test::makeTempDir("cfg_simsensor");
  fs::copy_file(test::repoDir() + "/rawlogs/live_sim.ini", dir + "/live_sim.ini");
  const std::string path = dir + "/live_typo.ini";
  std::ofstream(path) << withTypo(readText(dir + "/live_sim.ini"),
                                  "driver        = CSimulatedGyro\n",
                                  "driver        = CSimulatedGyro\ngrab_decimaton = 1\n");
  std::string out;
  EXPECT_EQ(test::runCommand(exe() + " config " + path, &out), 2) << out;
  expectTypoMessage(out, path, "GYRO_SENSOR", "grab_decimaton", "grab_decimation");
  // The live app loads the section through MRPT's CGenericSensor::loadConfig.
  EXPECT_EQ(test::runCommand("cd " + dir + " && timeout 60 " + exe() + " live " + path +
                                 " -o " + dir + "/live.rawlog",
                             &out),
            2)
      << out;
  expectTypoMessage(out, path, "GYRO_SENSOR", "grab_decimaton", "grab_decimation");
}

TEST(ConfigCommand, MontecarloRunFileTypo) {
  const std::string dir = test::makeTempDir("cfg_mc"), out_dir = test::makeTempDir("cfg_mc_out");
  std::string out;
  ASSERT_EQ(test::runCommand(exe() + " montecarlo star-count --runs 3 --no-plots --shard 0/1 --out " + dir, &out), 0)
      << out;
  const std::string path = dir + "/star-count_run.txt";
  ASSERT_TRUE(fs::exists(path));
  ASSERT_EQ(test::runCommand(exe() + " config " + path, &out), 0) << out;
  EXPECT_NE(out.find("[montecarlo_run]"), std::string::npos) << out;
  std::ofstream(path + ".tmp") << withTypo(readText(path), "\nseed =", "\nsed =");
  fs::rename(path + ".tmp", path);
  EXPECT_EQ(test::runCommand(exe() + " config " + path, &out), 2) << out;
  expectTypoMessage(out, path, "montecarlo_run", "sed", "seed");
  EXPECT_EQ(test::runCommand(exe() + " montecarlo merge " + dir + " --no-plots --out " + out_dir, &out), 2)
      << out;
  expectTypoMessage(out, path, "montecarlo_run", "sed", "seed");
}

/// A typo must fail `startracker config FILE` and the command that uses the file (`using`,
/// run from the file's folder) alike, with exit code 2 and the same message.
void expectRefusedByBoth(const std::string& path, const std::string& using_cmd,
                         const std::string& section, const std::string& key,
                         const std::string& expected) {
  SCOPED_TRACE(key);
  const std::string dir = fs::path(path).parent_path().string();
  for (const std::string& cmd : {exe() + " config " + path, "cd " + dir + " && " + using_cmd}) {
    std::string out;
    EXPECT_EQ(test::runCommand(cmd, &out), 2) << cmd << "\n" << out;
    EXPECT_NE(out.find(path), std::string::npos) << out;
    EXPECT_TRUE(out.find("[" + section + "] key '" + key + "'") != std::string::npos ||
                out.find("section '" + section + "' key '" + key + "'") != std::string::npos)
        << out;
    EXPECT_NE(out.find(expected), std::string::npos) << out;
  }
}

TEST(ConfigCommand, TrackerIniTyposAndOldNamesFailInEverySection) {
  const std::string dir = test::makeTempDir("cfg_tracker");
  const std::string sample = readText(test::repoDir() + "/rawlogs/tracker.ini");
  const std::string replay = exe() + " replay " + test::repoDir() + "/rawlogs/hold.rawlog -q --config ";
  const std::vector<Typo> typos = {
      {"filter", "bias_sigma_deg_h =", "bias_sigma_deg_hh =", "bias_sigma_deg_hh", "bias_sigma_deg_h"},
      {"pipeline", "read_noise_adu =", "read_noise_adux =", "read_noise_adux", "read_noise_adu"},
      {"pipeline", "read_noise_adu =", "track_gate_sigm = 3\nread_noise_adu =", "track_gate_sigm",
       "track_gate_sigma"},
      {"navigator", "[pipeline]", "[navigator]\ngyro_labl = GYRO\n[pipeline]", "gyro_labl", "gyro_label"},
      {"database", "[pipeline]", "[database]\nmag_limt = 6\n[pipeline]", "mag_limt", "mag_limit"},
  };
  for (const Typo& t : typos) {
    const std::string path = dir + "/typo_" + t.key + ".ini";
    std::ofstream(path) << withTypo(sample, t.from, t.to);
    expectRefusedByBoth(path, replay + path, t.section, t.key, "did you mean '" + t.suggestion + "'?");
  }
  // An old key name is refused naming its new one.
  const std::string path = dir + "/old_name.ini";
  std::ofstream(path) << withTypo(sample, "read_noise_adu =", "gate_sigma = 3\nread_noise_adu =");
  expectRefusedByBoth(path, replay + path, "pipeline", "gate_sigma", "renamed to 'track_gate_sigma'");
}

TEST(ConfigCommand, LiveIniTyposAndOldNamesFailInItsOwnAndSensorSections) {
  const std::string dir = test::makeTempDir("cfg_live");
  fs::copy_file(test::repoDir() + "/rawlogs/live_sim.ini", dir + "/live_sim.ini");
  const std::string sample = readText(dir + "/live_sim.ini");
  const std::vector<Typo> typos = {
      {"global", "rawlog_file =", "rawlog_fil =", "rawlog_fil", "rawlog_file"},
      {"filter", "bias_sigma_deg_h =", "bias_sigma_deg_hh =", "bias_sigma_deg_hh", "bias_sigma_deg_h"},
      {"navigator", "enabled          =", "enable           =", "enable", "enabled"},
      {"TRACKER_SENSOR", "mag_limit     =", "mag_limt      =", "mag_limt", "mag_limit"},
      {"TRACKER_SENSOR", "emit_image    =", "emit_imag     =", "emit_imag", "emit_image"},
      {"TRACKER_SENSOR", "track_solver  =", "track_solvr   =", "track_solvr", "track_solver"},
  };
  for (const Typo& t : typos) {
    const std::string path = dir + "/typo_" + t.key + ".ini";
    std::ofstream(path) << withTypo(sample, t.from, t.to);
    expectRefusedByBoth(path, "timeout 60 " + exe() + " live " + path + " -o " + dir + "/x.rawlog",
                        t.section, t.key, "did you mean '" + t.suggestion + "'?");
  }
  const std::string path = dir + "/old_name.ini";
  std::ofstream(path) << withTypo(sample, "track_solver  =", "solver        =");
  expectRefusedByBoth(path, "timeout 60 " + exe() + " live " + path + " -o " + dir + "/x.rawlog",
                      "TRACKER_SENSOR", "solver", "renamed to 'track_solver' and 'lis_solver'");
}

/// The printed configuration without its first line (which names the file printed) and
/// without the notes on sections no schema printed (the print has no such sections).
std::string body(const std::string& out) {
  return std::regex_replace(out.substr(out.find('\n') + 1),
                            std::regex("# \\[[^\\]]*\\]: no schema registered[^\n]*\n"), "");
}

TEST(ConfigCommand, EverySampleIniPrintsAConfigurationThatReadsBack) {
  const std::string dir = test::makeTempDir("cfg_samples");
  std::set<std::string> without_schema;
  int printed = 0;
  for (const char* folder : {"/rawlogs", "/tests/data"}) {
    for (const auto& e : fs::recursive_directory_iterator(test::repoDir() + folder)) {
      if (e.path().extension() != ".ini") continue;
      SCOPED_TRACE(e.path().string());
      std::string out;
      const int rc = test::runCommand(exe() + " config " + e.path().string() + " 2>&1", &out);
      if (rc == 2 && out.find("no known schema") != std::string::npos) {
        without_schema.insert(e.path().filename().string());
        continue;
      }
      ASSERT_EQ(rc, 0) << out;
      ++printed;
      const std::string copy = dir + "/" + e.path().filename().string();
      std::ofstream(copy) << body(out);
      std::string again;
      ASSERT_EQ(test::runCommand(exe() + " config " + copy, &again), 0) << again;
      EXPECT_EQ(body(again), body(out));
    }
  }
  EXPECT_GE(printed, 8);
  // Every sample has a schema now: tracker.ini files and the live app's sections included.
  EXPECT_EQ(without_schema, std::set<std::string>{});
}

}  // namespace
}  // namespace st
