// AttitudeMekf speed (issue 8: propagation < 1 us, attitude-fix update < 5 us).
#include <benchmark/benchmark.h>

#include "common/attitude.hpp"
#include "common/conventions.hpp"
#include "fusion/mekf.hpp"

namespace st {
namespace {

AttitudeMekf makeFilter() {
  AttitudeMekf f(MekfOptions::fromDatasheet(0.3, 3.0, 20));
  f.initialize(0, attitudeFromRaDecRoll({1.0, 0.3, 0.2}), Mat3::Identity() * 1e-8);
  return f;
}

void BM_MekfPropagate(benchmark::State& state) {
  AttitudeMekf f = makeFilter();
  const Vec3 w(0.01, -0.02, 0.005);
  double t = 0;
  for (auto _ : state) {
    t += 0.01;
    f.propagate(w, t);
    benchmark::DoNotOptimize(f.covariance().data());
  }
}
BENCHMARK(BM_MekfPropagate);

void BM_MekfAttitudeFixUpdate(benchmark::State& state) {
  AttitudeMekf f = makeFilter();
  const Quat q = f.attitude();
  const Mat3 R = Vec3(1e-10, 1e-10, 4e-8).asDiagonal();
  const Mat6 P = f.covariance();
  for (auto _ : state) {
    // Restore the covariance so every update sees the same (not collapsing) state.
    f.initialize(0, q, f.bias(), P);
    benchmark::DoNotOptimize(f.updateAttitude(q, R).nis);
  }
}
BENCHMARK(BM_MekfAttitudeFixUpdate);

void BM_MekfInitializeOnly(benchmark::State& state) {  // the restore cost above, to subtract
  AttitudeMekf f = makeFilter();
  const Quat q = f.attitude();
  const Mat6 P = f.covariance();
  for (auto _ : state) {
    f.initialize(0, q, f.bias(), P);
    benchmark::DoNotOptimize(f.covariance().data());
  }
}
BENCHMARK(BM_MekfInitializeOnly);

void BM_MekfStarVectorUpdate(benchmark::State& state) {
  AttitudeMekf f = makeFilter();
  const Quat q = f.attitude();
  const Mat6 P = f.covariance();
  std::vector<StarVectorMeasurement> stars;
  for (int k = 0; k < state.range(0); ++k) {
    const Vec3 b = Vec3(0.1 * std::cos(k), 0.1 * std::sin(k), 1.0).normalized();
    stars.push_back(StarVectorMeasurement::fromSigma(b, q * b, arcsec2rad(5)));
  }
  for (auto _ : state) {
    f.initialize(0, q, f.bias(), P);
    benchmark::DoNotOptimize(f.updateStarVectors(stars).nis);
  }
}
BENCHMARK(BM_MekfStarVectorUpdate)->Arg(1)->Arg(2)->Arg(5)->Arg(10)->Arg(20);

void BM_MekfPredictAt(benchmark::State& state) {
  AttitudeMekf f = makeFilter();
  f.propagate(Vec3(0.01, 0.02, 0.03), 0.01);
  for (auto _ : state) benchmark::DoNotOptimize(f.predictAt(0.05).P.data());
}
BENCHMARK(BM_MekfPredictAt);

}  // namespace
}  // namespace st

BENCHMARK_MAIN();
