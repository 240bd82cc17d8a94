// The effective scenario printed by printScenarioIni loads back to the same scenario, value
// for value, for every sample scenario in rawlogs/ (the regression set of the schemas).
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <filesystem>

#include "sensors/sim/scenario.hpp"
#include "tests/support/test_paths.hpp"
#include "sensors/mrpt/camera_ini.hpp"

namespace st {
namespace {
namespace fs = std::filesystem;

void expectSameScenario(const Scenario& a, const Scenario& b) {
  EXPECT_EQ(a.duration_s, b.duration_s);
  EXPECT_EQ(a.frame_rate_hz, b.frame_rate_hz);
  EXPECT_EQ(a.start_unix_s, b.start_unix_s);
  EXPECT_EQ(a.seed, b.seed);
  EXPECT_EQ(a.database_path, b.database_path);
  EXPECT_EQ(a.catalog_path, b.catalog_path);
  EXPECT_EQ(a.mag_limit, b.mag_limit);
  EXPECT_EQ(a.aberration, b.aberration);
  EXPECT_EQ(a.camera.width(), b.camera.width());
  EXPECT_EQ(a.camera.height(), b.camera.height());
  EXPECT_EQ(a.camera.fx(), b.camera.fx());
  EXPECT_EQ(a.camera.fy(), b.camera.fy());
  EXPECT_EQ(a.camera.cx(), b.camera.cx());
  EXPECT_EQ(a.camera.cy(), b.camera.cy());
  EXPECT_EQ(a.camera.distortion().k1, b.camera.distortion().k1);
  EXPECT_EQ(a.sensor.aperture_diameter_m, b.sensor.aperture_diameter_m);
  EXPECT_EQ(a.sensor.read_noise_e, b.sensor.read_noise_e);
  EXPECT_EQ(a.sensor.gain_e_per_adu, b.sensor.gain_e_per_adu);
  EXPECT_EQ(a.sensor.hot_pixels, b.sensor.hot_pixels);
  EXPECT_EQ(a.sensor.hot_pixel_seed, b.sensor.hot_pixel_seed);
  ASSERT_TRUE(a.motion && b.motion);
  EXPECT_EQ(a.motion->type(), b.motion->type());
  for (double t : {0.0, 0.7, a.duration_s}) {
    EXPECT_EQ(a.motion->attitude(t).coeffs(), b.motion->attitude(t).coeffs()) << t;
    EXPECT_EQ(a.motion->rateBody(t), b.motion->rateBody(t)) << t;
  }
  ASSERT_EQ(a.gyro.has_value(), b.gyro.has_value());
  if (a.gyro) {
    EXPECT_EQ(a.gyro->rate_hz, b.gyro->rate_hz);
    EXPECT_EQ(a.gyro->arw_deg_rt_h, b.gyro->arw_deg_rt_h);
    EXPECT_EQ(a.gyro->rrw_deg_h_rt_h, b.gyro->rrw_deg_h_rt_h);
    EXPECT_EQ(a.gyro_initial_bias_rad_s, b.gyro_initial_bias_rad_s);
  }
  EXPECT_EQ(a.faults.spikes_per_frame, b.faults.spikes_per_frame);
  EXPECT_EQ(a.faults.false_stars, b.faults.false_stars);
  EXPECT_EQ(a.faults.drop_frame_probability, b.faults.drop_frame_probability);
  EXPECT_EQ(a.faults.dropouts, b.faults.dropouts);
  EXPECT_EQ(a.faults.blinding_center_px, b.faults.blinding_center_px);
}

TEST(ScenarioConfig, EverySampleScenarioPrintsAndReadsBackTheSameValues) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(test::repoDir() + "/rawlogs")) {
    if (e.path().extension() != ".ini") continue;
    const std::string path = e.path().string();
    const mrpt::config::CConfigFile file(path);
    if (!file.sectionExists("scenario")) continue;
    SCOPED_TRACE(path);
    const std::string dir = e.path().parent_path().string();
    const Scenario original = Scenario::fromConfig(file, path, dir);
    const std::string printed = printScenarioIni(readScenarioIni(IniReader{file, path}));
    const mrpt::config::CConfigFileMemory back(printed);
    expectSameScenario(original, Scenario::fromConfig(back, "printed", dir));
    // A fixed point: printing what was read from the print gives the same text.
    EXPECT_EQ(printScenarioIni(readScenarioIni(IniReader{back, "printed"})), printed);
    ++n;
  }
  EXPECT_GE(n, 6);
}

TEST(ScenarioConfig, FovAndExplicitCameraFormsAreExclusive) {
  const mrpt::config::CConfigFileMemory both(
      "[C]\nresolution = [100 100]\nfov_deg = 10\nfx = 500\n");
  try {
    loadCameraIni(both, "C", "cam.ini");
    FAIL() << "fov_deg with fx must be refused";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cam.ini: [C] key 'fx': give either fov_deg"),
              std::string::npos)
        << e.what();
  }
}

TEST(ScenarioConfig, OneQuantityInTwoUnitsIsRefused) {
  // aperture_diameter_mm is a read-only alias of aperture_diameter_m: both at once would be
  // two answers, and the printed configuration keeps only the metre key.
  const mrpt::config::CConfigFileMemory both(
      "[sensor]\naperture_diameter_mm = 25\naperture_diameter_m = 0.03\n");
  try {
    SensorParams::fromConfig(IniReader{both, "s.ini"}, "sensor");
    FAIL() << "both units must be refused";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("s.ini: [sensor] key 'aperture_diameter_mm'"),
              std::string::npos)
        << e.what();
  }
  const mrpt::config::CConfigFileMemory mm("[sensor]\naperture_diameter_mm = 25\n");
  EXPECT_DOUBLE_EQ(SensorParams::fromConfig(IniReader{mm, "s.ini"}, "sensor").aperture_diameter_m,
                   0.025);
}

}  // namespace
}  // namespace st
