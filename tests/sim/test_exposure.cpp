// Exposure from the body rate (seed 004 sec. 4.2: longer integration, more light, but
// streaks at higher tumble rates): the longest exposure whose smear stays under a set length.
// At 1 deg/s the rendered streaks of the chosen exposure stay under 3 px; the fixed 0.2 s
// exposure draws ~13 px streaks.
#include <gtest/gtest.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "sensors/detect/exposure.hpp"
#include "sensors/sim/scenario.hpp"
#include "sensors/sim/star_renderer.hpp"

namespace st {
namespace {

const CameraModel kCam = CameraModel::fromFov(1024, 1024, deg2rad(15.0));

TEST(ExposureFromRate, SpeedAndClamp) {
  const double w = deg2rad(1.0);
  // About a cross axis a pinhole moves the principal point by fx * omega, the rim more
  // (1 + tan^2 of the off-axis angle): at the corners of 15 deg x 15 deg, 1 + 2 tan^2(7.5 deg).
  const double centre = kCam.fx() * w;
  const double fast = maxImageSpeedPxPerS(kCam, Vec3(w, 0, 0));
  EXPECT_GE(fast, centre);
  EXPECT_LE(fast, centre * (1 + 2 * std::pow(std::tan(deg2rad(7.5)), 2)) * 1.001);
  // About the boresight the corners move r * omega, r the half diagonal in pixels.
  EXPECT_NEAR(maxImageSpeedPxPerS(kCam, Vec3(0, 0, w)), std::hypot(511.5, 511.5) * w, 0.01 * w * 724);
  const double t = exposureForRate(kCam, Vec3(w, 0, 0), 3.0, 1e-3, 0.2);
  EXPECT_NEAR(t * fast, 3.0, 1e-9);
  EXPECT_DOUBLE_EQ(exposureForRate(kCam, Vec3::Zero(), 3.0, 1e-3, 0.2), 0.2);
  EXPECT_DOUBLE_EQ(exposureForRate(kCam, Vec3(deg2rad(500.0), 0, 0), 3.0, 1e-3, 0.2), 1e-3);
}

/// [px] Length of each isolated star's streak, from the second moments of its noiseless image:
/// a uniform streak of length L through a Gaussian PSF has variance sigma^2 + L^2 / 12 along
/// it and sigma^2 across, so L = sqrt(12 (lambda_max - lambda_min)).
std::vector<double> streakLengths(const cv::Mat& e, const std::vector<TrueStar>& truth) {
  std::vector<double> out;
  for (const TrueStar& s : truth) {
    const int cx = static_cast<int>(std::lround(s.px.x())), cy = static_cast<int>(std::lround(s.px.y()));
    if (cx < 25 || cy < 25 || cx >= e.cols - 25 || cy >= e.rows - 25) continue;
    bool isolated = true;
    for (const TrueStar& o : truth)
      isolated = isolated && (&o == &s || (o.px - s.px).norm() > 40);
    if (!isolated) continue;
    double m = 0, mx = 0, my = 0, xx = 0, yy = 0, xy = 0;
    for (int y = cy - 20; y <= cy + 20; ++y)
      for (int x = cx - 20; x <= cx + 20; ++x) {
        const double v = e.at<double>(y, x);
        m += v, mx += v * x, my += v * y, xx += v * x * x, yy += v * y * y, xy += v * x * y;
      }
    mx /= m, my /= m;
    const double a = xx / m - mx * mx, b = yy / m - my * my, c = xy / m - mx * my;
    const double d = std::sqrt(0.25 * (a - b) * (a - b) + c * c);
    out.push_back(std::sqrt(12 * std::max(0.0, 2 * d)));  // lambda_max - lambda_min = 2 d
  }
  return out;
}

std::shared_ptr<const StarSource> randomSky(int n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g;
  std::vector<SkyStar> stars;
  for (int i = 0; i < n; ++i)
    stars.push_back({static_cast<uint32_t>(i + 1), Vec3(g(rng), g(rng), g(rng)).normalized(), 4.0});
  return std::make_shared<ListStarSource>(stars);
}

const char* kScenario = R"(
[scenario]
duration_s = 1.0
frame_rate_hz = 5
start_time = 2025-06-01T12:00:00
seed = 5
[camera]
resolution = [1024 1024]
fov_deg = 15
[sensor]
exposure_s = 0.2
max_smear_px = 3
bit_depth = 12
[motion]
type = slew
ra_deg = 40
dec_deg = 20
rate_deg_s = 0.6 0.8 0.0
)";

TEST(ExposureFromRate, SimulatorStreaksStayUnderTheSetLengthAtOneDegPerSecond) {
  mrpt::config::CConfigFileMemory cfg(kScenario);
  const Scenario sc = Scenario::fromConfig(cfg, "exposure.ini");
  ASSERT_DOUBLE_EQ(sc.sensor.max_smear_px, 3.0);
  const auto sky = randomSky(20000, 3);
  const SkySimulator sim(sc, 1, sky);
  StarRenderer renderer(sc.camera, sc.sensor, *sky);
  for (int k = 0; k < sc.frameCount(); ++k) {
    const SimFrame f = sim.frame(k);
    EXPECT_NEAR(rad2deg(f.rate_body.norm()), 1.0, 1e-9);
    EXPECT_LT(f.exposure_s, 0.2);
    EXPECT_NEAR(f.exposure_s * maxImageSpeedPxPerS(sc.camera, f.rate_body), 3.0, 1e-9);
    // The frame's own light: its exposure, drawn the way the simulator draws it.
    RenderOptions with_rule;
    with_rule.exposure_s = f.exposure_s;
    cv::Mat e = cv::Mat::zeros(1024, 1024, CV_64F), e_fixed = e.clone();
    const auto truth = renderer.render(constantRateAttitude(f.q_ib, f.rate_body), e, with_rule);
    const auto truth_fixed = renderer.render(constantRateAttitude(f.q_ib, f.rate_body), e_fixed);
    const std::vector<double> L = streakLengths(e, truth), L_fixed = streakLengths(e_fixed, truth_fixed);
    ASSERT_GE(L.size(), 5u);
    const double longest = *std::max_element(L.begin(), L.end());
    const double longest_fixed = *std::max_element(L_fixed.begin(), L_fixed.end());
    std::printf("frame %d: exposure %.4f s, %zu streaks, longest %.3f px (fixed 0.2 s: %.2f px)\n",
                k, f.exposure_s, L.size(), longest, longest_fixed);
    // The moments of a row of sub-step PSFs 0.5 sigma apart give L to ~1e-3 px.
    EXPECT_LE(longest, 3.0 + 0.01);
    EXPECT_GT(longest, 2.7);  // the exposure is the longest allowed, not merely a short one
    EXPECT_GT(longest_fixed, 12.0);
    // The simulator's frame holds the light of its exposure: the stars' electrons scale.
    ASSERT_FALSE(f.truth.empty());
    EXPECT_NEAR(f.truth.front().electrons, sc.sensor.starElectrons(4.0) * f.exposure_s / 0.2,
                1e-6 * f.truth.front().electrons);
  }
}

TEST(ExposureFromRate, BadKeysNameTheKey) {
  const std::string base = std::string(kScenario);
  for (const auto& [line, key] : {std::pair<std::string, std::string>{"max_smear_px = -1", "max_smear_px"},
                                  {"min_exposure_s = 0.5", "min_exposure_s"}}) {
    std::string text = base;
    text.replace(text.find("max_smear_px = 3"), 16, line);
    mrpt::config::CConfigFileMemory cfg(text);
    try {
      Scenario::fromConfig(cfg, "exposure.ini");
      ADD_FAILURE() << line << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace st
