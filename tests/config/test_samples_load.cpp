// The regression set: every sample .ini still loads through the readers that use it, now
// that the readers are strict (tracker files through the navigator's reader, sensor
// sections through MRPT's loadConfig, scenarios through Scenario::load).
#include <gtest/gtest.h>

#include <algorithm>
#include <mrpt/config/CConfigFile.h>

#include <filesystem>

#include "common/conventions.hpp"
#include "navigation/tracker_config.hpp"
#include "sensors/mrpt/star_tracker_sensor.hpp"
#include "sensors/sim/scenario.hpp"
#include "sensors/sim/simulated_sensors.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {
namespace fs = std::filesystem;

/// Runs `f` with the working directory set to `dir` (sensor sections name files relative
/// to where the app runs).
template <class F>
void inDirectory(const std::string& dir, F f) {
  const fs::path before = fs::current_path();
  fs::current_path(dir);
  try {
    f();
  } catch (...) {
    fs::current_path(before);
    throw;
  }
  fs::current_path(before);
}

TEST(SampleIni, EveryRawlogsIniLoadsThroughItsReaders) {
  const std::string dir = test::repoDir() + "/rawlogs";
  int sections = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() != ".ini") continue;
    const std::string path = e.path().string();
    SCOPED_TRACE(path);
    const mrpt::config::CConfigFile cfg(path);
    if (cfg.sectionExists("scenario")) {
      EXPECT_NO_THROW(Scenario::load(path));
      ++sections;
    }
    std::vector<std::string> all;
    cfg.getAllSections(all);
    const bool live = std::any_of(all.begin(), all.end(), [&](const std::string& s) {
      return !cfg.read_string(s, "driver", "", false).empty();
    });
    if (live && (cfg.sectionExists("filter") || cfg.sectionExists("navigator"))) {
      bool enabled = false;
      EXPECT_NO_THROW(liveNavigatorOptions(cfg, path, &enabled));
      ++sections;
    } else if (cfg.sectionExists("filter") || cfg.sectionExists("pipeline")) {
      EXPECT_NO_THROW(TrackerConfig::load(path));
      ++sections;
    }
    registerSimulatedSensors();  // a tracker's simulated image source is created by name
    for (const auto& s : all) {
      const std::string driver = cfg.read_string(s, "driver", "", false);
      if (driver.empty()) continue;
      SCOPED_TRACE(s);
      std::unique_ptr<mrpt::hwdrivers::CGenericSensor> sensor;
      if (driver == "CStarTrackerSensor") sensor = std::make_unique<CStarTrackerSensor>();
      if (driver == "CSimulatedGyro") sensor = std::make_unique<CSimulatedGyro>();
      if (driver == "CSimulatedStarCamera") sensor = std::make_unique<CSimulatedStarCamera>();
      // An MRPT driver of the examples (an IMU beside the camera): MRPT's own loadConfig.
      std::shared_ptr<mrpt::hwdrivers::CGenericSensor> mrpt_sensor;
      if (!sensor) mrpt_sensor = mrpt::hwdrivers::CGenericSensor::createSensorPtr(driver);
      mrpt::hwdrivers::CGenericSensor* any = sensor ? sensor.get() : mrpt_sensor.get();
      ASSERT_TRUE(any) << "no such driver " << driver;
      // The real-camera examples name the calibration the user writes (cam.yaml): load them
      // where one exists.
      const std::string cam = cfg.read_string(s, "camera_file", "", false);
      std::string where = dir;
      if (!cam.empty() && !fs::exists(dir + "/" + cam)) {
        where = test::makeTempDir("sample_ini_camera");
        fs::create_directories(fs::path(where + "/" + cam).parent_path());
        CameraModel::fromFov(1024, 768, deg2rad(11.4)).saveYaml(where + "/" + cam);
      }
      // CStarTrackerSensor hands its section to an inner CSimulatedStarCamera: the inner
      // camera must leave the tracker's own keys to the tracker.
      inDirectory(where, [&] { EXPECT_NO_THROW(any->loadConfig(cfg, s)); });
      ++sections;
    }
  }
  EXPECT_GE(sections, 10);
}

}  // namespace
}  // namespace st
