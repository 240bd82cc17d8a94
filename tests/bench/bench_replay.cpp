// Replay throughput of the navigator (pipeline + MEKF) in tracking mode on 1024 x 1024 12-bit
// frames, one core (issue 9 target: >= 500 frames/s, i.e. <= 2000 us per frame):
//   BM_ReplayTrackingFrame  one iteration = one frame period: 10 GYRO samples (100 Hz) and one
//                           CAMERA frame pushed through the navigator (reorder buffer,
//                           propagation, prediction, windows, QUEST, update). Images are in
//                           memory: decoding is excluded and measured separately below.
//   BM_DecodePng1024        decoding one such frame from PNG (what a rawlog with external
//                           images adds per frame).
#include <benchmark/benchmark.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <opencv2/imgcodecs.hpp>

#include "common/conventions.hpp"
#include "navigation/navigator.hpp"
#include "navigation/tracker_config.hpp"
#include "sensors/sim/scenario.hpp"
#include "sensors/sim/sim_observations.hpp"

namespace st {
namespace {

struct Data {
  Scenario sc;
  std::unique_ptr<StarDatabase> db;
  std::vector<cv::Mat> images;
  std::vector<Vec3> rates;  // 10 per frame
};

const Data& data() {
  static const Data d = [] {
    Data out;
    // A hold (frames can be cycled with fresh timestamps) with sensor noise and a real gyro.
    mrpt::config::CConfigFileMemory cfg(
        "[scenario]\nduration_s = 1.6\nframe_rate_hz = 10\nstart_time = 2025-03-20T00:00:00\n"
        "seed = 4\nmag_limit = 6.5\n[camera]\nresolution = [1024 1024]\nfov_deg = 15\n"
        "[sensor]\naperture_diameter_mm = 25\nexposure_s = 0.1\npsf_sigma_px = 1.2\n"
        "read_noise_e = 8\nfull_well_e = 30000\ngain_e_per_adu = 8\nbit_depth = 12\n"
        "[motion]\ntype = hold\nra_deg = 84\ndec_deg = -2\n"
        "[gyro]\nrate_hz = 100\narw_deg_rt_h = 0.15\nrrw_deg_h_rt_h = 0.5\n[faults]\n");
    out.sc = Scenario::fromConfig(cfg, "bench");
    SkySimulator sim(out.sc, 4);
    for (int k = 0; k < out.sc.frameCount(); ++k) out.images.push_back(sim.frame(k).image);
    GyroSample g;
    while (sim.nextGyro(g)) out.rates.push_back(g.rate);
    DatabaseSource src;
    out.db = std::make_unique<StarDatabase>(*makeDatabase(src, out.sc.camera, out.sc.epochJyear()));
    return out;
  }();
  return d;
}

void BM_ReplayTrackingFrame(benchmark::State& state) {
  const Data& d = data();
  NavigatorOptions o;
  o.pipeline.tracker.exposure_s = d.sc.sensor.exposure_s;
  o.pipeline.tracker.detect.gain_e_per_adu = d.sc.sensor.gain();
  o.pipeline.tracker.detect.read_noise_adu = d.sc.sensor.read_noise_e / d.sc.sensor.gain();
  o.fusion.filter = MekfOptions::fromDatasheet(0.15, 0.5, 5.0);
  Navigator nav(*d.db, d.sc.camera, o);
  nav.setKeepSteps(false);
  int frames = 0, tracking = 0;
  nav.setStepCallback([&](const NavStep& s, const std::vector<CObservationStarTracker::Ptr>&) {
    ++frames;
    tracking += s.mode == StarTrackerMode::kTracking;
  });
  const std::size_t nf = d.images.size();
  std::vector<mrpt::obs::CObservationImage::Ptr> cams;
  for (std::size_t k = 0; k < nf; ++k)
    cams.push_back(makeCameraObservation(d.images[k], d.sc.camera, d.sc.timestamp(0)));
  std::vector<mrpt::obs::CObservationIMU::Ptr> gyros;
  for (int j = 0; j < 10; ++j) gyros.push_back(makeGyroObservation(Vec3::Zero(), d.sc.timestamp(0)));
  long step = 0;
  auto pushFrame = [&] {
    for (int j = 0; j < 10; ++j) {
      auto& g = gyros[j];
      const long n = step * 10 + j + 1;
      g->timestamp = d.sc.timestamp(0.01 * double(n));
      const Vec3 r = d.rates[std::size_t(n) % d.rates.size()];
      g->rawMeasurements[mrpt::obs::IMU_WX] = r.x();
      g->rawMeasurements[mrpt::obs::IMU_WY] = r.y();
      g->rawMeasurements[mrpt::obs::IMU_WZ] = r.z();
      nav.push(g);
    }
    auto& c = cams[std::size_t(step) % nf];
    c->timestamp = d.sc.timestamp(0.1 * double(step + 1));
    nav.push(c);
    ++step;
  };
  for (int k = 0; k < 3; ++k) pushFrame();  // lost-in-space, then tracking
  for (auto _ : state) pushFrame();
  state.counters["frames_per_s"] =
      benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["tracking_fraction"] = frames > 3 ? double(tracking) / double(frames) : 0.0;
  state.counters["target_us"] = 2000;  // 500 frames/s
}
BENCHMARK(BM_ReplayTrackingFrame)->Unit(benchmark::kMicrosecond);

void BM_DecodePng1024(benchmark::State& state) {
  std::vector<uchar> png;
  cv::imencode(".png", data().images[0], png);
  for (auto _ : state) {
    cv::Mat m = cv::imdecode(png, cv::IMREAD_UNCHANGED);
    benchmark::DoNotOptimize(m.data);
  }
  state.counters["png_kB"] = double(png.size()) / 1024.0;
}
BENCHMARK(BM_DecodePng1024)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace st
BENCHMARK_MAIN();
