// Simulator speed: one 1024x1024 frame with 100 stars (target < 20 ms), split into the
// signal rendering (PSF, blur) and the detector (noise + digitisation).
#include <benchmark/benchmark.h>

#include <random>

#include "common/conventions.hpp"
#include "sensors/sim/detector.hpp"
#include "sensors/sim/star_renderer.hpp"

namespace {

using namespace st;

struct Setup {
  CameraModel cam = CameraModel::fromFov(1024, 1024, deg2rad(15.0));
  SensorParams sensor;
  Quat q_ib = attitudeFromRaDecRoll({1.0, 0.4, 0.2});
  std::unique_ptr<ListStarSource> stars;
  Setup() {
    sensor.bit_depth = 16;
    sensor.gain_e_per_adu = 1;
    sensor.hot_pixels = 50;
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> ux(0, 1023), mag(1.0, 7.0);
    std::vector<SkyStar> s;
    const Mat3 R = q_ib.toRotationMatrix();
    for (uint32_t i = 1; i <= 100; ++i)
      s.push_back({i, (R * cam.pixelToVector({ux(rng), ux(rng)})).normalized(), mag(rng)});
    stars = std::make_unique<ListStarSource>(s);
  }
};

void renderFrame(benchmark::State& state, double rate_deg_s) {
  Setup s;
  const Detector det(s.sensor, s.cam.width(), s.cam.height());
  const StarRenderer r(s.cam, s.sensor, *s.stars);
  const cv::Mat background = det.meanBackground();
  const AttitudeAt q_at = constantRateAttitude(s.q_ib, Vec3(0, deg2rad(rate_deg_s), 0));
  std::mt19937_64 rng(2);
  std::size_t n_truth = 0;
  for (auto _ : state) {
    cv::Mat e = background.clone();
    n_truth = r.render(q_at, e).size();
    cv::Mat img = det.expose(e, rng);
    benchmark::DoNotOptimize(img.data);
  }
  state.counters["stars"] = static_cast<double>(n_truth);
  state.counters["substeps"] = r.lastSubsteps();
}

void BM_Frame1024_100Stars_Hold(benchmark::State& state) { renderFrame(state, 0.0); }
void BM_Frame1024_100Stars_Slew2dps(benchmark::State& state) { renderFrame(state, 2.0); }

void BM_SignalOnly1024_100Stars_Slew2dps(benchmark::State& state) {
  Setup s;
  const StarRenderer r(s.cam, s.sensor, *s.stars);
  const AttitudeAt q_at = constantRateAttitude(s.q_ib, Vec3(0, deg2rad(2.0), 0));
  cv::Mat e(s.cam.height(), s.cam.width(), CV_64FC1, cv::Scalar(0));
  for (auto _ : state) {
    r.render(q_at, e);
    benchmark::DoNotOptimize(e.data);
  }
  state.counters["substeps"] = r.lastSubsteps();
}

void BM_DetectorExpose1024(benchmark::State& state) {
  Setup s;
  const Detector det(s.sensor, s.cam.width(), s.cam.height());
  const cv::Mat background = det.meanBackground();
  std::mt19937_64 rng(3);
  for (auto _ : state) {
    cv::Mat img = det.expose(background, rng);
    benchmark::DoNotOptimize(img.data);
  }
}

BENCHMARK(BM_Frame1024_100Stars_Hold)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Frame1024_100Stars_Slew2dps)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SignalOnly1024_100Stars_Slew2dps)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DetectorExpose1024)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
