// StarTracker frame cost on simulated 800x600 12-bit frames (tests/tracking/tracker_sim.hpp):
//   BM_TrackingFrame     prediction given -> cone query, projection, 20 windows, gate, QUEST,
//                        verification (issue 7 target: < 100 us)
//   BM_LostInSpaceFrame  the same frames from scratch: full-frame detection + pyramid
// The ratio of the two is the speed-up of tracking (issue 7 target: >= 20x).
#include <benchmark/benchmark.h>

#include <random>

#include "sensors/tracking/star_tracker.hpp"
#include "tests/tracking/tracker_sim.hpp"

namespace st {
namespace {

struct Frames {
  std::vector<test::FrameSimulator::Frame> frames;
  std::vector<AttitudePrediction> predictions;
};

const Frames& frames() {
  static const Frames f = [] {
    Frames out;
    const SlewMotion motion(attitudeFromRaDecRoll({deg2rad(84.0), deg2rad(-2.0), deg2rad(25.0)}),
                            Vec3(deg2rad(1.0), deg2rad(-0.5), deg2rad(0.2)));
    test::FrameSimulator sim(42);
    std::mt19937_64 rng(1);
    std::normal_distribution<double> n01;
    const double sigma = arcsec2rad(20.0);
    for (int k = 0; k < 16; ++k) {
      out.frames.push_back(sim.frame(motion, 0.1 * k));
      AttitudePrediction p;
      p.q_ib = motion.attitude(0.1 * k) * quatExp(sigma * Vec3(n01(rng), n01(rng), n01(rng)));
      p.cov_body = sigma * sigma * Mat3::Identity();
      p.rate_body = motion.rateBody(0.1 * k);
      out.predictions.push_back(p);
    }
    return out;
  }();
  return f;
}

// Arg 0: the default centroider ("gauss" ML fit), 1: "cog" (cheaper, less accurate).
void BM_TrackingFrame(benchmark::State& state) {
  const Frames& f = frames();
  TrackerOptions opts = test::simTrackerOptions();
  if (state.range(0) == 1) opts.detect.centroider = "cog";
  opts.max_tracked_stars = 20;
  StarTracker pipe(test::simDatabase(), test::simCamera(), opts);
  pipe.process(f.frames[0].image, f.frames[0].t_s);  // lost-in-space once: not lost any more
  std::size_t k = 0;
  int stars = 0, tracked = 0, frames_done = 0;
  for (auto _ : state) {
    const std::size_t i = k++ % f.frames.size();
    FrameInputs in;
    in.prediction = f.predictions[i];
    const FrameResult o = pipe.process(f.frames[i].image, f.frames[i].t_s, in);
    stars += int(o.stars.size());
    tracked += o.mode == StarTrackerMode::kTracking;
    ++frames_done;
    benchmark::DoNotOptimize(o);
  }
  state.counters["stars"] = double(stars) / frames_done;
  state.counters["tracked"] = double(tracked) / frames_done;
  state.counters["target_us"] = 100;  // issue 7
}
BENCHMARK(BM_TrackingFrame)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

void BM_LostInSpaceFrame(benchmark::State& state) {
  const Frames& f = frames();
  StarTracker pipe(test::simDatabase(), test::simCamera(), test::simTrackerOptions());
  std::size_t k = 0;
  int solved = 0, frames_done = 0;
  for (auto _ : state) {
    const std::size_t i = k++ % f.frames.size();
    pipe.reset();
    const FrameResult o = pipe.process(f.frames[i].image, f.frames[i].t_s);
    solved += o.mode == StarTrackerMode::kLostInSpace;
    ++frames_done;
    benchmark::DoNotOptimize(o);
  }
  state.counters["solved"] = double(solved) / frames_done;
}
BENCHMARK(BM_LostInSpaceFrame)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace st

BENCHMARK_MAIN();
