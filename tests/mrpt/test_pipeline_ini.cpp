// The pipeline's .ini keys (sensors/mrpt/pipeline_ini.hpp), shared by CStarTrackerSensor and
// the navigator's [pipeline]: every key is read into its own option, the stages' same-named
// options have distinct prefixed keys, old key names are refused naming the new ones, and a
// bad value or name is refused naming the file, section and key.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cstdlib>
#include <sstream>

#include "sensors/attitude/wahba.hpp"
#include "sensors/detect/centroider.hpp"
#include "sensors/identify/identifier.hpp"
#include "common/errors.hpp"
#include "sensors/mrpt/pipeline_ini.hpp"

namespace st {
namespace {

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

/// A value of the same type as the printed `def`, different from it.
std::string otherValue(const std::string& def) {
  if (def == "true") return "false";
  if (def == "false") return "true";
  // A key restricted to a registry's names (centroider, solvers, identifier): another name.
  for (const auto& names : {Centroider::names(), WahbaSolver::names(), StarIdentifier::names()})
    for (const std::string& n : names)
      if (n == def) return names.front() == def ? names.back() : names.front();
  char* end = nullptr;
  const double d = std::strtod(def.c_str(), &end);
  if (!def.empty() && *end == '\0') return formatIniNumber(d + 1);
  return "x" + def;
}

TEST(PipelineIni, EveryKeyIsReadIntoItsOwnOption) {
  const auto& schema = pipelineIniSchema();
  const PipelineOptions def;
  const std::vector<std::string> def_lines = lines(schema.print("pipeline", def));
  for (const auto& k : schema.keys()) {
    SCOPED_TRACE(k.name);
    if (k.name == "detect_dark_file") continue;  // reads its file: tests/app/test_dark.cpp
    const std::string value = otherValue(k.write(def));
    mrpt::config::CConfigFileMemory cfg("[pipeline]\n" + k.name + " = " + value + "\n");
    PipelineOptions o;
    schema.read(IniReader{cfg, "t.ini"}, "pipeline", o);
    // Exactly the key's own line changes: two keys bound to one option would change two.
    const std::vector<std::string> got = lines(schema.print("pipeline", o));
    ASSERT_EQ(got.size(), def_lines.size());
    std::vector<std::string> changed;
    for (std::size_t i = 0; i < got.size(); ++i)
      if (got[i] != def_lines[i]) changed.push_back(got[i]);
    EXPECT_EQ(changed, std::vector<std::string>{k.name + " = " + value});
  }
}

TEST(PipelineIni, SameNamedOptionsOfTheStagesHaveTheirOwnKeys) {
  mrpt::config::CConfigFileMemory cfg(
      "[pipeline]\ntrack_gate_sigma = 3.5\nverify_gate_sigma = 6\ntrack_edge_margin_px = 7\n"
      "verify_edge_margin_px = 2\ndetect_max_stars = 50\nlis_max_stars = 9\n"
      "track_solver = svd\nlis_solver = foam\nlis_min_sigma_px = 0.03\ntrack_min_sigma_px = 0.002\n"
      "f2f_enabled = false\n");
  PipelineOptions o;
  readPipelineOptions(IniReader{cfg, "t.ini"}, "pipeline", o);
  const TrackerOptions& t = o.tracker;
  EXPECT_EQ(t.gate_sigma, 3.5);
  EXPECT_EQ(t.identify.verify.gate_sigma, 6.0);
  EXPECT_EQ(t.edge_margin_px, 7.0);
  EXPECT_EQ(t.identify.verify.edge_margin_px, 2.0);
  EXPECT_EQ(t.detect.max_stars, 50);
  EXPECT_EQ(t.identify.max_stars, 9);
  EXPECT_EQ(t.solver, "svd");
  EXPECT_EQ(t.identify.solver, "foam");
  EXPECT_EQ(t.min_sigma_px, 0.03);
  EXPECT_EQ(t.tracking_min_sigma_px, 0.002);
  EXPECT_FALSE(t.frame_to_frame);
}

std::string message(const std::string& key, const std::string& value) {
  mrpt::config::CConfigFileMemory cfg("[pipeline]\n" + key + " = " + value + "\n");
  PipelineOptions o;
  try {
    readPipelineOptions(IniReader{cfg, "t.ini"}, "pipeline", o);
  } catch (const InputError& e) {
    return std::string(e.what());
  }
  return std::string("no error");
}

TEST(PipelineIni, OldKeyNamesAreRefusedNamingTheNewName) {
  for (const auto& [old_key, new_key] : pipelineIniSchema().renamedKeys()) {
    SCOPED_TRACE(old_key);
    EXPECT_THAT(message(old_key, "1"),
                ::testing::HasSubstr("t.ini: [pipeline] key '" + old_key + "': renamed to '" +
                                     new_key.substr(0, new_key.find(' ')) + "'"));
  }
  EXPECT_THAT(message("solver", "quest"),
              ::testing::HasSubstr("renamed to 'track_solver' and 'lis_solver'"));
  EXPECT_GE(pipelineIniSchema().renamedKeys().size(), 22u);
}

TEST(PipelineIni, BadValuesAndNamesAreRefusedWithFileSectionAndKey) {
  using ::testing::HasSubstr;
  EXPECT_THAT(message("track_gate_sigma", "3x"), HasSubstr("t.ini: [pipeline] track_gate_sigma"));
  EXPECT_THAT(message("detect_max_stars", "2.5"), HasSubstr("detect_max_stars: not an integer"));
  EXPECT_THAT(message("detect_reject_spikes", "maybe"), HasSubstr("detect_reject_spikes"));
  EXPECT_THAT(
      message("track_gate_sigm", "3"),
      HasSubstr("[pipeline] key 'track_gate_sigm': unknown key; did you mean 'track_gate_sigma'?"));
  // Values checked once by TrackerOptions::isValid: reported under the key the user wrote.
  EXPECT_THAT(message("lis_algorithm", "nonsense"), HasSubstr("key 'lis_algorithm'"));
  EXPECT_THAT(message("lis_solver", "nonsense"), HasSubstr("key 'lis_solver'"));
  EXPECT_THAT(message("track_solver", "nonsense"), HasSubstr("key 'track_solver'"));
  EXPECT_THAT(message("track_min_stars", "2"), HasSubstr("key 'track_min_stars'"));
  EXPECT_THAT(message("track_gate_sigma", "0"), HasSubstr("key 'track_gate_sigma'"));
  EXPECT_THAT(message("verify_gate_sigma", "0"), HasSubstr("key 'verify_gate_sigma'"));
  EXPECT_THAT(message("detect_max_stars", "0"), HasSubstr("key 'detect_max_stars'"));
  EXPECT_THAT(message("lis_max_stars", "2"), HasSubstr("key 'lis_max_stars'"));
  EXPECT_THAT(message("gain_e_per_adu", "0"), HasSubstr("key 'gain_e_per_adu'"));
  EXPECT_THAT(message("lis_min_sigma_px", "0"), HasSubstr("key 'lis_min_sigma_px'"));
  EXPECT_THAT(message("track_min_sigma_px", "0"), HasSubstr("key 'track_min_sigma_px'"));
  // The sensor's messages avoid ']' (MRPT's stacked exceptions cut there).
  mrpt::config::CConfigFileMemory cfg("[pipeline]\ntrack_gate_sigma = -1\n");
  PipelineOptions o;
  try {
    readPipelineOptions(IniReader{cfg, "", true}, "pipeline", o);
    ADD_FAILURE() << "track_gate_sigma = -1 accepted";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("section 'pipeline' key 'track_gate_sigma'"));
    EXPECT_EQ(std::string(e.what()).find(']'), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace st
