// The pipeline's .ini keys (sensors/mrpt/pipeline_ini.hpp), shared by CStarTrackerSensor and
// the navigator's [pipeline]: every listed key is read into its option, and a bad value or
// name is refused naming the file, section and key.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <map>

#include "common/errors.hpp"
#include "sensors/mrpt/pipeline_ini.hpp"

namespace st {
namespace {

// A valid value for every key, each different from PipelineOptions' default.
const std::map<std::string, std::string> kValues = {
    {"sensor_label", "ST2"},         {"lis_algorithm", "voting"},
    {"solver", "svd"},               {"identify_solver", "foam"},
    {"exposure_s", "0.05"},          {"min_sigma_px", "0.03"},
    {"tracking_min_sigma_px", "0.002"}, {"max_tracked_stars", "12"},
    {"min_tracked_stars", "5"},      {"drop_saturated", "false"},
    {"gate_sigma", "4"},             {"edge_margin_px", "6"},
    {"blend_separation_px", "7"},    {"loss_probability", "0.01"},
    {"consistency_probability", "0.02"}, {"max_failed_frames", "5"},
    {"frame_to_frame", "false"},     {"max_propagation_s", "2"},
    {"accel_sigma", "0.1"},          {"gyro_sigma", "2e-4"},
    {"gain_e_per_adu", "8"},         {"read_noise_adu", "3"},
    {"threshold_sigma", "6"},        {"centroider", "iwc"},
    {"psf_sigma_px", "1.4"},         {"reject_spikes", "true"},
    {"max_stars", "77"},             {"identify_max_stars", "9"},
    {"pair_sigma", "5"}};

std::string ini(const std::map<std::string, std::string>& kv) {
  std::string s = "[pipeline]\n";
  for (const auto& [k, v] : kv) s += k + " = " + v + "\n";
  return s;
}

TEST(PipelineIni, EveryKeyIsListedAndReadIntoItsOption) {
  ASSERT_EQ(pipelineIniKeys().size(), kValues.size());
  for (const auto& [k, v] : kValues) EXPECT_EQ(pipelineIniKeys().count(k), 1u) << k;
  const PipelineOptions def;
  for (const auto& [key, value] : kValues) {
    mrpt::config::CConfigFileMemory cfg(ini({{key, value}}));
    PipelineOptions o;
    readPipelineOptions(IniReader{cfg, "t.ini"}, "pipeline", o);
    // Each key alone must change exactly the option it names: compare the printable fields.
    auto fields = [](const PipelineOptions& po) {
      const TrackerOptions& p = po.tracker;
      return std::vector<std::string>{
          po.sensor_label, p.lis_algorithm, p.solver, p.identify.solver,
          std::to_string(p.exposure_s), std::to_string(p.min_sigma_px),
          std::to_string(p.tracking_min_sigma_px), std::to_string(p.max_tracked_stars),
          std::to_string(p.min_tracked_stars), std::to_string(p.drop_saturated),
          std::to_string(p.gate_sigma), std::to_string(p.edge_margin_px),
          std::to_string(p.blend_separation_px), std::to_string(p.loss_probability),
          std::to_string(p.consistency_probability), std::to_string(p.max_failed_frames),
          std::to_string(p.frame_to_frame), std::to_string(p.max_propagation_s),
          std::to_string(p.accel_sigma), std::to_string(p.gyro_sigma),
          std::to_string(p.detect.gain_e_per_adu), std::to_string(p.detect.read_noise_adu),
          std::to_string(p.detect.threshold_sigma), p.detect.centroider,
          std::to_string(p.detect.psf_sigma_px), std::to_string(p.detect.reject_spikes),
          std::to_string(p.detect.max_stars), std::to_string(p.identify.max_stars),
          std::to_string(p.identify.pair_sigma)};
    };
    const auto a = fields(def), b = fields(o);
    int changed = 0;
    for (std::size_t i = 0; i < a.size(); ++i) changed += a[i] != b[i];
    // `solver` names the solver of tracking and of lost-in-space alike.
    EXPECT_EQ(changed, key == "solver" ? 2 : 1) << key << " = " << value;
  }
}

TEST(PipelineIni, BadValuesAndNamesAreRefusedWithFileSectionAndKey) {
  auto message = [](const std::string& key, const std::string& value) {
    mrpt::config::CConfigFileMemory cfg(ini({{key, value}}));
    PipelineOptions o;
    try {
      readPipelineOptions(IniReader{cfg, "t.ini"}, "pipeline", o);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_THAT(message("gate_sigma", "3x"), ::testing::HasSubstr("t.ini: [pipeline] gate_sigma"));
  EXPECT_THAT(message("max_stars", "2.5"), ::testing::HasSubstr("max_stars: not an integer"));
  EXPECT_THAT(message("reject_spikes", "maybe"), ::testing::HasSubstr("reject_spikes"));
  EXPECT_THAT(message("lis_algorithm", "nonsense"), ::testing::HasSubstr("lis_algorithm"));
  EXPECT_THAT(message("identify_solver", "nonsense"), ::testing::HasSubstr("identify_solver"));
  EXPECT_THAT(message("min_tracked_stars", "2"), ::testing::HasSubstr("min_tracked_stars"));
  // The sensor's messages avoid ']' (MRPT's stacked exceptions cut there).
  mrpt::config::CConfigFileMemory cfg(ini({{"gate_sigma", "-1"}}));
  PipelineOptions o;
  try {
    readPipelineOptions(IniReader{cfg, "", true}, "pipeline", o);
    ADD_FAILURE() << "gate_sigma = -1 accepted";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("section 'pipeline'"));
    EXPECT_EQ(std::string(e.what()).find(']'), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace st
