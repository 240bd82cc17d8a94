// The gyroless filter step (issue 16): what one frame costs the filter without a gyro, i.e.
// the prediction to the frame time (closed-form constant-rate propagation,
// fusion/gyroless_model.hpp) and the attitude-fix update, and the tracker's frame-to-frame
// rate (sensors/tracking/frame_rate.hpp) over 20 common stars.
#include <benchmark/benchmark.h>

#include <cmath>

#include "common/attitude.hpp"
#include "common/conventions.hpp"
#include "fusion/mekf.hpp"
#include "sensors/tracking/frame_rate.hpp"

namespace st {
namespace {

AttitudeMekf makeFilter() {
  MekfOptions o;
  o.model = MekfOptions::Model::kGyroless;
  o.rate_walk_rad_s2_rt_hz = 1e-3;
  AttitudeMekf f(o);
  f.initialize(0, attitudeFromRaDecRoll({1.0, 0.3, 0.2}), Vec3(0.01, -0.005, 0.003),
               Vec6(1e-9, 1e-9, 4e-8, 1e-6, 1e-6, 1e-6).asDiagonal().toDenseMatrix());
  return f;
}

void BM_GyrolessPredict(benchmark::State& state) {
  AttitudeMekf f = makeFilter();
  double t = 0;
  for (auto _ : state) {
    t += 0.1;
    f.predictTo(t);
    benchmark::DoNotOptimize(f.covariance().data());
  }
}
BENCHMARK(BM_GyrolessPredict);

/// One frame's filter work: predict 0.2 s ahead, then the fix update (the state restored
/// each time so that every update sees the same covariance).
void BM_GyrolessFilterStep(benchmark::State& state) {
  AttitudeMekf f = makeFilter();
  const Quat q = f.attitude();
  const Vec3 w = f.bias();
  const Mat6 P = f.covariance();
  const Mat3 R = Vec3(1e-10, 1e-10, 4e-8).asDiagonal();
  const Quat q_meas = q * quatExp(w * 0.2);
  for (auto _ : state) {
    f.initialize(0, q, w, P);
    f.predictTo(0.2);
    benchmark::DoNotOptimize(f.updateAttitude(q_meas, R).nis);
  }
}
BENCHMARK(BM_GyrolessFilterStep);

void BM_GyrolessInitializeOnly(benchmark::State& state) {  // the restore cost above
  AttitudeMekf f = makeFilter();
  const Quat q = f.attitude();
  const Vec3 w = f.bias();
  const Mat6 P = f.covariance();
  for (auto _ : state) {
    f.initialize(0, q, w, P);
    benchmark::DoNotOptimize(f.covariance().data());
  }
}
BENCHMARK(BM_GyrolessInitializeOnly);

void BM_FrameRate20Stars(benchmark::State& state) {
  RateFrame a, b;
  a.t_s = 0;
  b.t_s = 0.2;
  a.sigma = b.sigma = arcsec2rad(5);
  const Mat3 A12 = quatExp(Vec3(0.002, -0.001, 0.003)).toRotationMatrix();
  for (int k = 0; k < 20; ++k) {
    const Vec3 v2 = Vec3(0.1 * std::cos(k), 0.1 * std::sin(1.7 * k), 1.0).normalized();
    a.ids.push_back(k);
    b.ids.push_back(k);
    a.v_cam.push_back(A12 * v2);
    b.v_cam.push_back(v2);
  }
  for (auto _ : state) benchmark::DoNotOptimize(measureFrameRate(a, b, Mat3::Identity()));
}
BENCHMARK(BM_FrameRate20Stars);

}  // namespace
}  // namespace st

BENCHMARK_MAIN();
