// CStarTrackerSensor: configured from an .ini section on the simulated star camera it emits one
// STAR_TRACKER fix per frame (tracking after the start, consistent with the truth), takes an
// external prediction, names the section and key of bad configuration, and runs inside the
// stock rawlog-grabber through the plugin.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/obs/CObservation6DFeatures.h>
#include <mrpt/obs/CObservationImage.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <thread>

#include "common/attitude.hpp"
#include "common/errors.hpp"
#include "sensors/mrpt/rawlog_io.hpp"
#include "sensors/mrpt/star_tracker_sensor.hpp"
#include "sensors/sim/scenario.hpp"
#include "sensors/sim/sim_observations.hpp"
#include "sensors/sim/simulated_sensors.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

namespace fs = std::filesystem;

// 1.5 s inertial hold on Orion, 10 Hz, 512 x 512 px, 15 deg (rawlogs/hold.ini's sensor).
const char* kScenario = R"(
[scenario]
duration_s     = 1.5
frame_rate_hz  = 10
start_time     = 2025-03-20T00:00:00
seed           = 3
mag_limit      = 7.0
[camera]
resolution = [512 512]
fov_deg    = 15
[sensor]
aperture_diameter_mm = 25
transmission         = 0.8
qe                   = 0.6
exposure_s           = 0.1
psf_sigma_px         = 1.0
sky_e_px_s           = 5
dark_current_e_px_s  = 20
read_noise_e         = 8
full_well_e          = 20000
gain_e_per_adu       = 8
bit_depth            = 8
bias_adu             = 8
[motion]
type     = hold
ra_deg   = 84.0
dec_deg  = -2.0
roll_deg = 0
[gyro]
rate_hz            = 100
arw_deg_rt_h       = 0.15
rrw_deg_h_rt_h     = 0.5
bias_deg_h         = 0
[faults]
)";

// chi-square(3) quantile at 0.999: a per-frame NEES above it is a 1-in-1000 event.
constexpr double kChi2_3_999 = 16.266;

std::string writeScenario(const std::string& dir) {
  const std::string path = dir + "/scenario.ini";
  std::ofstream(path) << kScenario;
  return path;
}

std::string trackerSection(const std::string& scenario, const std::string& extra = "") {
  return "[TRACKER]\n"
         "driver = CStarTrackerSensor\n"
         "process_rate = 50\n"
         "image_source = simulated\n"
         "scenario_file = " + scenario + "\n" + extra;
}

struct PlayResult {
  std::vector<CObservationStarTracker::Ptr> fixes;
  std::map<int64_t, Quat> truth;  // by timestamp ticks
  int images = 0;
  int other = 0;
};

// Plays the scenario through the sensor in real time (as a grabber thread does).
PlayResult play(CStarTrackerSensor& sensor) {
  PlayResult run;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (!sensor.sourceFinished() && std::chrono::steady_clock::now() < deadline) {
    sensor.doProcess();
    for (auto& [t, obj] : sensor.getObservations()) {
      if (auto f = std::dynamic_pointer_cast<CObservationStarTracker>(obj)) {
        run.fixes.push_back(f);
      } else if (auto g = std::dynamic_pointer_cast<mrpt::obs::CObservation6DFeatures>(obj)) {
        run.truth[g->timestamp.time_since_epoch().count()] = truthFromObservation(*g).q_ib;
      } else if (std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(obj)) {
        ++run.images;
      } else {
        ++run.other;
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return run;
}

std::unique_ptr<CStarTrackerSensor> makeSensor(const std::string& ini) {
  registerSimulatedSensors();  // image_source = simulated creates it by name
  mrpt::config::CConfigFileMemory cfg(ini);
  auto s = std::make_unique<CStarTrackerSensor>();
  s->loadConfig(cfg, "TRACKER");
  s->initialize();
  return s;
}

TEST(StarTrackerSensor, SimulatedCameraGivesTrackingFixesConsistentWithTruth) {
  const std::string dir = test::makeTempDir("st_sensor");
  resetSimulatedSensorsClock();
  auto sensor = makeSensor(trackerSection(writeScenario(dir)));
  const PlayResult run = play(*sensor);

  ASSERT_TRUE(sensor->sourceFinished()) << "the 1.5 s scenario did not finish in 20 s";
  // One fix per delivered frame, each with its frame and its truth (frames the process was
  // too slow for are skipped by the camera, not half-delivered).
  ASSERT_GE(run.fixes.size(), 10u);
  EXPECT_EQ(run.images, static_cast<int>(run.fixes.size()));
  EXPECT_EQ(run.truth.size(), run.fixes.size());
  EXPECT_EQ(sensor->framesProcessed(), static_cast<int>(run.fixes.size()));

  int tracking = 0;
  for (std::size_t k = 0; k < run.fixes.size(); ++k) {
    const auto& f = *run.fixes[k];
    EXPECT_EQ(f.sensorLabel, "STAR_TRACKER");
    ASSERT_TRUE(f.hasAttitude()) << "frame " << k << ": " << f.reason;
    if (f.mode == StarTrackerMode::kTracking) ++tracking;
    const auto it = run.truth.find(f.timestamp.time_since_epoch().count());
    ASSERT_NE(it, run.truth.end()) << "no truth at the fix's timestamp, frame " << k;
    EXPECT_LT(attitudeNees(f.q_ib, f.cov_body, it->second), kChi2_3_999) << "frame " << k;
  }
  // Frame-to-frame mode: frame 0 is lost-in-space, frame 1 too (no rate yet: one attitude),
  // every later frame tracks.
  EXPECT_EQ(run.fixes[0]->mode, StarTrackerMode::kLostInSpace);
  EXPECT_GE(tracking, static_cast<int>(run.fixes.size()) - 2);
  EXPECT_EQ(sensor->framesSolved(), static_cast<int>(run.fixes.size()));
  EXPECT_EQ(sensor->framesTracking(), tracking);

  // Teeth of the consistency check: a truth off by 20 arcsec across the boresight fails it.
  const auto& f0 = *run.fixes.back();
  const Quat off = run.truth.rbegin()->second * quatExp(Vec3(1e-4, 0, 0));
  EXPECT_GT(attitudeNees(f0.q_ib, f0.cov_body, off), kChi2_3_999);
}

TEST(StarTrackerSensor, ExternalPredictionMakesTheSecondFrameTrack) {
  const std::string dir = test::makeTempDir("st_sensor_pred");
  const std::string scen = writeScenario(dir);
  resetSimulatedSensorsClock();
  // No frame-to-frame mode: only the external prediction can make a frame track.
  auto sensor = makeSensor(trackerSection(scen, "f2f_enabled = false\nemit_image = false\n"));
  const Scenario sc = Scenario::load(scen);
  int asked = 0;
  sensor->setInputsProvider([&](mrpt::Clock::time_point t) {
    ++asked;
    const double dt =
        std::chrono::duration<double>(t - sc.timestamp(0)).count();  // the scenario's clock
    AttitudePrediction p;
    p.q_ib = sc.motion->attitude(dt) * quatExp(Vec3(2e-5, -1e-5, 3e-5));  // a small error
    p.cov_body = Mat3::Identity() * 1e-8;
    p.rate_body = sc.motion->rateBody(dt);
    FrameInputs in;
    in.prediction = p;
    return in;
  });
  const PlayResult run = play(*sensor);
  ASSERT_GE(run.fixes.size(), 10u);
  EXPECT_EQ(run.images, 0);  // emit_image = false
  EXPECT_EQ(asked, static_cast<int>(run.fixes.size()));
  EXPECT_EQ(run.fixes[0]->mode, StarTrackerMode::kLostInSpace);  // lost: prediction ignored
  for (std::size_t k = 1; k < run.fixes.size(); ++k)
    EXPECT_EQ(run.fixes[k]->mode, StarTrackerMode::kTracking) << "frame " << k;

  // Teeth: the same configuration without the predictor never tracks.
  resetSimulatedSensorsClock();
  auto bare = makeSensor(trackerSection(scen, "f2f_enabled = false\nemit_image = false\n"));
  const PlayResult none = play(*bare);
  ASSERT_FALSE(none.fixes.empty());
  EXPECT_EQ(bare->framesTracking(), 0);
}

// Configuration errors name the section and the key. CGenericSensor::loadConfig wraps our
// InputError in MRPT's stacked exception: the message must survive.
struct BadKey {
  std::string extra;       // replaces / adds keys
  bool drop_source;        // remove image_source
  std::string must_name;   // key named in the message
};

std::string loadError(const std::string& ini, bool init) {
  registerSimulatedSensors();
  try {
    mrpt::config::CConfigFileMemory cfg(ini);
    CStarTrackerSensor s;
    s.loadConfig(cfg, "TRACKER");
    if (init) s.initialize();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(StarTrackerSensor, BadConfigurationNamesSectionAndKey) {
  const std::string dir = test::makeTempDir("st_sensor_bad");
  const std::string scen = writeScenario(dir);
  const std::vector<BadKey> cases = {
      {"", true, "image_source"},
      {"lis_algorithm = no_such_algorithm\n", false, "lis_algorithm"},
      {"track_solver = no_such_solver\n", false, "key 'track_solver'"},
      {"lis_solver = no_such_solver\n", false, "key 'lis_solver'"},
      {"track_gate_sigma = abc\n", false, "track_gate_sigma"},
      {"track_min_stars = 1\n", false, "key 'track_min_stars'"},
      {"detect_max_stars = 0\n", false, "key 'detect_max_stars'"},
      {"verify_gate_sigma = 0\n", false, "key 'verify_gate_sigma'"},
      {"gate_sigma = 3\n", false, "key 'gate_sigma': renamed to 'track_gate_sigma'"},
      {"track_gate_sigm = 3\n", false, "key 'track_gate_sigm': unknown key; did you mean 'track_gate_sigma'?"},
      {"emit_image = perhaps\n", false, "emit_image"},
      {"database_file = /no/such/db.bin\n", false, "database_file"},
      {"camera_file = /no/such/camera.yaml\n", false, "camera_file"},
  };
  for (const auto& c : cases) {
    std::string ini = trackerSection(scen, c.extra);
    if (c.drop_source) ini = std::regex_replace(ini, std::regex("image_source = simulated\n"), "");
    const std::string msg = loadError(ini, false);
    EXPECT_THAT(msg, ::testing::HasSubstr("section 'TRACKER'")) << c.must_name;
    EXPECT_THAT(msg, ::testing::HasSubstr(c.must_name)) << msg;
  }
  // Other sources and missing keys of a source.
  const std::string no_scenario =
      "[TRACKER]\nprocess_rate = 10\nimage_source = simulated\n";
  EXPECT_THAT(loadError(no_scenario, false), ::testing::HasSubstr("scenario_file"));
  const std::string unknown_source = "[TRACKER]\nprocess_rate = 10\nimage_source = webcam\n";
  EXPECT_THAT(loadError(unknown_source, false), ::testing::HasSubstr("webcam"));
  const std::string camera_no_calib = "[TRACKER]\nprocess_rate = 10\nimage_source = camera\n";
  EXPECT_THAT(loadError(camera_no_calib, false), ::testing::HasSubstr("camera_file"));
  // A camera file that exists but is not a calibration: reported at initialize().
  const std::string junk = dir + "/junk.yaml";
  std::ofstream(junk) << "not: a camera\n";
  const std::string msg = loadError(trackerSection(scen, "camera_file = " + junk + "\n"), true);
  EXPECT_THAT(msg, ::testing::HasSubstr("section 'TRACKER' key 'camera_file'"));
  // Teeth: the good configuration loads without error.
  EXPECT_EQ(loadError(trackerSection(scen), false), "");
}

TEST(StarTrackerSensor, RegisteredWithMrptSensorFactory) {
  registerStarTrackerClasses();
  auto s = mrpt::hwdrivers::CGenericSensor::createSensorPtr("CStarTrackerSensor");
  ASSERT_TRUE(s);
  EXPECT_NE(dynamic_cast<CStarTrackerSensor*>(s.get()), nullptr);
}

#ifdef ST_MRPT_PLUGIN_PATH
// The stock rawlog-grabber loads the plugin, runs the sensor from grab.ini and records its
// fixes; the stock rawlog-edit lists them. rawlog-grabber quits on end-of-file on stdin
// (MRPT-NOTES.md): stdin stays open on `sleep` for 12 s, and its end makes the grabber
// quit cleanly (a signal would kill it mid-write and truncate the gz file).
TEST(StarTrackerSensor, StockRawlogGrabberRecordsStarTrackerFixes) {
  const std::string dir = test::makeTempDir("st_grabber");
  const std::string scen = writeScenario(dir);
  const std::string ini = dir + "/grab.ini";
  std::ofstream(ini) << "[global]\n"
                        "rawlog_prefix = " + dir + "/grab\n"
                        "time_between_launches = 100\n"
                        "use_sensoryframes = 0\n"
                        "GRABBER_PERIOD_MS = 50\n"
                        "rawlog_GZ_compress_level = 1\n\n"
                     << trackerSection(scen, "sensorLabel = STAR_TRACKER\n");
  std::string out;
  test::runCommand("sleep 12 | timeout 60 " ST_PLUGIN_HOST_ENV "rawlog-grabber -p '"
                   ST_MRPT_PLUGIN_PATH "," ST_SIM_PLUGIN_PATH "' '" + ini + "'",
                   &out);
  std::string rawlog;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() == ".rawlog") rawlog = e.path().string();
  }
  ASSERT_FALSE(rawlog.empty()) << "rawlog-grabber wrote no rawlog:\n" << out;

  std::string info;
  ASSERT_EQ(test::runCommand(ST_PLUGIN_HOST_ENV "rawlog-edit -p '" ST_MRPT_PLUGIN_PATH
                                                "' --info -i '" + rawlog + "'",
                             &info),
            0)
      << info;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(info, m, std::regex(R"(STAR_TRACKER\s*/\s*(\d+)\s*/)"))) << info;
  EXPECT_GE(std::stoi(m[1]), 10) << info;  // 15 frames, a few may be skipped
  // Our reader agrees on every object.
  std::size_t fixes = 0;
  const auto all = readRawlog(rawlog);
  for (const auto& o : all) fixes += o->sensorLabel == "STAR_TRACKER";
  EXPECT_EQ(static_cast<int>(fixes), std::stoi(m[1]));
}
// The production plugin does not contain the simulator: with it alone, a tracker asking for
// the simulated camera is refused with a message naming the class and the plugin to load,
// and none of the simulator's code is in the library.
TEST(StarTrackerSensor, ProductionPluginDoesNotContainTheSimulator) {
  const std::string dir = test::makeTempDir("st_grabber_nosim");
  const std::string scen = writeScenario(dir);
  const std::string ini = dir + "/grab.ini";
  std::ofstream(ini) << "[global]\nrawlog_prefix = " + dir + "/grab\n"
                        "time_between_launches = 100\nuse_sensoryframes = 0\n"
                        "GRABBER_PERIOD_MS = 50\n\n"
                     << trackerSection(scen, "sensorLabel = STAR_TRACKER\n");
  std::string out;
  test::runCommand("sleep 3 | timeout 30 " ST_PLUGIN_HOST_ENV "rawlog-grabber -p '"
                   ST_MRPT_PLUGIN_PATH "' '" + ini + "'",
                   &out);
  EXPECT_THAT(out, ::testing::HasSubstr("CSimulatedStarCamera is not registered")) << out;
  std::string syms;
  ASSERT_EQ(test::runCommand("nm -C --defined-only '" ST_MRPT_PLUGIN_PATH "'", &syms), 0);
  EXPECT_THAT(syms, ::testing::HasSubstr("CStarTrackerSensor"));
  EXPECT_THAT(syms, ::testing::Not(::testing::HasSubstr("SkySimulator")));
  EXPECT_THAT(syms, ::testing::Not(::testing::HasSubstr("CSimulatedStarCamera")));
}
#endif

}  // namespace
}  // namespace st
