// Scenario -> rawlog: contents, labels, ordering, round trip of images and truth,
// determinism, faults, and the stock `rawlog-edit --info` on the committed samples.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/img/CImage.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/system/datetime.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <random>

#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "common/utc_time.hpp"
#include "sensors/sim/rawlog_writer.hpp"
#include "sensors/sim/scenario.hpp"
#include "sensors/sim/sim_observations.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

const char* kScenario = R"(
[scenario]
duration_s = 1.0
frame_rate_hz = 10
start_time = 2025-06-01T12:00:00
seed = 5
[camera]
resolution = [160 120]
fov_deg = 12
[sensor]
exposure_s = 0.05
gain_e_per_adu = 4
bit_depth = 8
hot_pixels = 3
[motion]
type = slew
ra_deg = 40
dec_deg = 20
rate_deg_s = 0.5 1.0 0.2
[gyro]
rate_hz = 50
arw_deg_rt_h = 0.2
rrw_deg_h_rt_h = 1
bias_deg_h = 2
[faults]
false_stars = 2
spikes_per_frame = 3
dropout_s = 0.25 0.45
)";

Scenario testScenario(const std::string& text = kScenario) {
  mrpt::config::CConfigFileMemory cfg(text);
  return Scenario::fromConfig(cfg, "test.ini");
}

// A random synthetic sky dense enough to put stars in a 12 deg field.
std::shared_ptr<const StarSource> randomSky(int n = 3000, uint64_t seed = 1) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> mag(1.0, 7.0);
  std::vector<SkyStar> stars;
  for (int i = 0; i < n; ++i)
    stars.push_back({static_cast<uint32_t>(i + 1), Vec3(g(rng), g(rng), g(rng)).normalized(), mag(rng)});
  return std::make_shared<ListStarSource>(stars);
}

TEST(Scenario, ParsesTheIniAndTheClock) {
  const Scenario sc = testScenario();
  EXPECT_EQ(sc.frameCount(), 10);
  EXPECT_EQ(sc.gyroSampleCount(), 50);
  EXPECT_EQ(sc.camera.width(), 160);
  ASSERT_TRUE(sc.gyro.has_value());
  EXPECT_EQ(sc.motion->type(), "slew");
  EXPECT_NEAR(sc.start_unix_s, 1748779200.0, 1e-6);  // 2025-06-01T12:00:00Z
  EXPECT_NEAR(mrpt::Clock::toDouble(sc.timestamp(0.3)), 1748779200.3, 1e-6);
  EXPECT_NEAR(sc.epochJyear(), 2025.415, 0.001);
  EXPECT_THROW(testScenario("[scenario]\nduration_s = 1\n"), InputError);  // no camera
  EXPECT_THROW(parseUtc("2025-13-01T00:00:00", "x"), InputError);
}

TEST(Scenario, FramesAreDeterministicPerSeedAndIndependentOfOrder) {
  const Scenario sc = testScenario();
  const auto sky = randomSky();
  SkySimulator a(sc, 7, sky), b(sc, 7, sky), c(sc, 8, sky);
  const SimFrame a5 = a.frame(5);
  b.frame(1), b.frame(2);
  const SimFrame b5 = b.frame(5);
  ASSERT_FALSE(a5.image.empty());
  EXPECT_EQ(cv::norm(a5.image, b5.image, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(a5.image, c.frame(5).image, cv::NORM_INF) > 0, true);
  ASSERT_EQ(a5.truth.size(), b5.truth.size());
  EXPECT_GT(a5.truth.size(), 3u);
  GyroSample ga, gb;
  for (int j = 0; j < 50; ++j) {
    ASSERT_TRUE(a.nextGyro(ga));
    ASSERT_TRUE(b.nextGyro(gb));
    EXPECT_EQ(ga.rate, gb.rate);
  }
  EXPECT_FALSE(a.nextGyro(ga));
  // Dropout [0.25, 0.45): frames 3 and 4 are not delivered, but their truth is known.
  EXPECT_TRUE(a.frame(3).dropped);
  EXPECT_TRUE(a.frame(4).image.empty());
  EXPECT_FALSE(a.frame(5).dropped);
  EXPECT_FALSE(a.frame(3).truth.empty());
  EXPECT_EQ(a.falseSources().size(), 2u);
}

TEST(SimRawlog, WrittenThenReadBackWithCRawlog) {
  const Scenario sc = testScenario();
  const std::string dir = test::makeTempDir("simrawlog");
  const std::string path = dir + "/run.rawlog";
  SimulateOptions opts;
  opts.progress = false;
  opts.stars = randomSky();
  const SimulateSummary sum = simulateToRawlog(sc, path, opts);
  EXPECT_EQ(sum.frames, 10);
  EXPECT_EQ(sum.frames_dropped, 2);
  EXPECT_EQ(sum.gyro_samples, 50);
  EXPECT_EQ(sum.objects, 10u + 8u + 50u);
  EXPECT_EQ(sum.images_dir, dir + "/run_Images");

  mrpt::obs::CRawlog log;
  ASSERT_TRUE(log.loadFromRawLogFile(path));
  ASSERT_EQ(log.size(), sum.objects);  // all objects came back (no silent truncation)
  mrpt::img::CImage::setImagesPathBase(sum.images_dir);
  std::map<std::string, int> count;
  mrpt::Clock::time_point prev{};
  SkySimulator sim(sc, sum.seed, opts.stars);
  int frame_k = 0;
  Vec3 gyro_err_sum = Vec3::Zero();
  for (std::size_t i = 0; i < log.size(); ++i) {
    ASSERT_EQ(log.getType(i), mrpt::obs::CRawlog::etObservation);
    const auto obs = log.getAsObservation(i);
    ++count[obs->sensorLabel];
    EXPECT_GE(obs->timestamp, prev) << "object " << i;
    prev = obs->timestamp;
    if (auto img = std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(obs)) {
      EXPECT_TRUE(img->image.isExternallyStored());
      const cv::Mat m = img->image.asCvMatRef();  // loads the PNG
      const double t = std::chrono::duration<double>(obs->timestamp - sc.timestamp(0)).count();
      const int k = static_cast<int>(std::lround(t * sc.frame_rate_hz));
      const SimFrame f = sim.frame(k);
      ASSERT_EQ(m.type(), CV_8UC1);
      EXPECT_EQ(cv::norm(m, f.image, cv::NORM_INF), 0.0) << "frame " << k;
      EXPECT_EQ(img->cameraParams.ncols, 160u);
      EXPECT_NEAR(img->cameraParams.fx(), sc.camera.fx(), 1e-9);
    } else if (auto gt = std::dynamic_pointer_cast<mrpt::obs::CObservation6DFeatures>(obs)) {
      const FrameTruth truth = truthFromObservation(*gt);
      const SimFrame f = sim.frame(frame_k++);
      EXPECT_LT(attitudeError(truth.q_ib, f.q_ib).total, 1e-12);
      ASSERT_EQ(truth.stars.size(), f.truth.size());
      for (std::size_t s = 0; s < truth.stars.size(); ++s) {
        EXPECT_EQ(truth.stars[s].id, f.truth[s].id);
        EXPECT_LT((truth.stars[s].px - f.truth[s].px).norm(), 1e-9);
        EXPECT_NEAR(truth.stars[s].mag, f.truth[s].mag, 1e-9);
      }
    } else if (auto imu = std::dynamic_pointer_cast<mrpt::obs::CObservationIMU>(obs)) {
      EXPECT_TRUE(imu->dataIsPresent[mrpt::obs::IMU_WX] && imu->dataIsPresent[mrpt::obs::IMU_WY] &&
                  imu->dataIsPresent[mrpt::obs::IMU_WZ]);
      // Rate = true slew rate (0.5, 1.0, 0.2) deg/s + white noise of sd ARW / sqrt(dt) per axis
      // (0.2 deg/sqrt(h) at 50 Hz: 0.0236 deg/s) + a 2 deg/h bias: |error| / sd is a
      // chi(3) variable, below 5.6 with probability 1 - 1e-6 (chi-square 3 dof: 30.7).
      const Vec3 err = rateFromObservation(*imu) * kDegPerRad - Vec3(0.5, 1.0, 0.2);
      const double sd = 0.2 / 60.0 * std::sqrt(50.0);
      EXPECT_LT(err.norm() / sd, 5.6);
      gyro_err_sum += err;
    } else {
      ADD_FAILURE() << "unexpected observation class";
    }
  }
  EXPECT_EQ(frame_k, 10);
  EXPECT_EQ(count["CAMERA"], 8);
  EXPECT_EQ(count["GROUND_TRUTH"], 10);
  EXPECT_EQ(count["GYRO"], 50);
  // The mean of 50 samples: sd 0.0236 / sqrt(50) = 0.0033 deg/s per axis, plus the bias
  // (2 deg/h = 0.00056 deg/s): within 5 sd + bias per axis.
  const Vec3 mean_err = gyro_err_sum / 50.0;
  for (int a = 0; a < 3; ++a)
    EXPECT_LT(std::abs(mean_err[a]), 5 * 0.2 / 60.0 + 2.0 / 3600.0) << "axis " << a;
  EXPECT_EQ(count.size(), 3u);

  // Determinism of the whole file for a seed.
  const std::string path2 = dir + "/run2.rawlog";
  simulateToRawlog(sc, path2, opts);
  for (int k : {0, 5, 9}) {
    char name[32];
    std::snprintf(name, sizeof(name), "CAMERA_%06d.png", k);
    const cv::Mat a = mrpt::img::CImage::LoadFromFile(dir + "/run_Images/" + name).asCvMat<cv::Mat>(mrpt::img::SHALLOW_COPY);
    const cv::Mat b = mrpt::img::CImage::LoadFromFile(dir + "/run2_Images/" + name).asCvMat<cv::Mat>(mrpt::img::SHALLOW_COPY);
    EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  }
}

TEST(SimRawlog, StockRawlogEditListsTheThreeLabelsOfTheSamples) {
  namespace fs = std::filesystem;
  for (const char* name : {"hold", "slew_2dps", "faults_dropout"}) {
    const std::string path = test::repoDir() + "/rawlogs/" + name + ".rawlog";
    ASSERT_TRUE(fs::exists(path)) << path;
    std::string out;
    const int rc = test::runCommand("/usr/bin/rawlog-edit --info -i '" + path + "'", &out);
    EXPECT_EQ(rc, 0) << out;
    EXPECT_NE(out.find("All sensor labels                 : CAMERA, GROUND_TRUTH, GYRO"), std::string::npos) << out;
  }
}

TEST(SimRawlog, DefaultCatalogSkyPutsRealStarsInTheFrame) {
  // The in-memory database from the committed Hipparcos subset: Orion's belt at the centre.
  Scenario sc = testScenario(std::string(kScenario) + "\n");
  sc.motion = std::make_shared<HoldMotion>(
      attitudeFromRaDecRoll({deg2rad(83.0), deg2rad(-1.0), 0.0}));
  SkySimulator sim(sc, 1);
  const SimFrame f = sim.frame(0);
  // Mintaka (HIP 25930), Alnilam (26311) and Alnitak (26727) within 12 x 9 deg of the centre.
  int belt = 0;
  for (const TrueStar& s : f.truth) belt += s.id == 25930 || s.id == 26311 || s.id == 26727;
  EXPECT_EQ(belt, 3);
  EXPECT_GT(f.truth.size(), 10u);
}

}  // namespace
}  // namespace st
