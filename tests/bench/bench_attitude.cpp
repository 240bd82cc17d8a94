// Wahba solvers on 4, 10 and 20 noisy star vectors in a 15 deg field: one solve() per
// iteration (validation and timing bookkeeping included, as the pipeline calls it). And the
// joint fix of 2 and 3 camera heads (joint_fix.hpp), once per multi-head step.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "common/conventions.hpp"
#include "sensors/attitude/joint_fix.hpp"
#include "sensors/attitude/wahba.hpp"

namespace {

std::vector<st::VectorObservation> makeObservations(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const st::Quat q_ib = st::canonical(st::Quat(g(rng), g(rng), g(rng), g(rng)));
  const double cmin = std::cos(st::deg2rad(7.5));
  std::vector<st::VectorObservation> obs;
  for (int k = 0; k < n; ++k) {
    const double c = 1.0 - u(rng) * (1.0 - cmin);
    const double s = std::sqrt(1.0 - c * c);
    const double phi = st::kTwoPi * u(rng);
    const st::Vec3 b(s * std::cos(phi), s * std::sin(phi), c);
    const double sigma = 5e-5 + 1.5e-4 * u(rng);
    st::Vec3 e(g(rng), g(rng), g(rng));
    e -= e.dot(b) * b;
    obs.push_back({(b + sigma * e).normalized(), q_ib * b, sigma});
  }
  return obs;
}

void BM_Wahba(benchmark::State& state, const std::string& name) {
  const auto solver = st::WahbaSolver::create(name);
  const auto obs = makeObservations(static_cast<int>(state.range(0)), 42);
  for (auto _ : state) {
    const st::WahbaSolution sol = solver->solve(obs);
    benchmark::DoNotOptimize(sol.q_ib);
    if (!sol.ok) state.SkipWithError(sol.reason.c_str());
  }
}

// The joint fix of N heads 90 deg apart, each fix 2" off across its boresight and 14" about
// it: a small part of a tracking frame (BM_TrackingFrame, 100 us target), so 5 us.
void BM_JointFix(benchmark::State& state) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g(0.0, 1.0);
  const st::Quat q = st::canonical(st::Quat(g(rng), g(rng), g(rng), g(rng)));
  const double s = st::arcsec2rad(2);
  std::vector<st::HeadFix> heads;
  for (int h = 0; h < state.range(0); ++h) {
    const st::Mat3 R = st::quatExp(st::deg2rad(90.0 * h) * st::Vec3(h % 2, (h + 1) % 2, 0).normalized())
                           .toRotationMatrix();
    const st::Mat3 cam = st::Vec3(s * s, s * s, 49 * s * s).asDiagonal();
    const st::Vec3 e(s * g(rng), s * g(rng), 7 * s * g(rng));
    heads.push_back({st::canonical(q * st::quatExp(R * e)), R * cam * R.transpose()});
  }
  for (auto _ : state) {
    const st::JointFix j = st::jointFix(heads);
    benchmark::DoNotOptimize(j.q_ib);
    if (!j.ok) state.SkipWithError(j.reason.c_str());
  }
  state.counters["target_us"] = 5.0;
}
BENCHMARK(BM_JointFix)->Arg(2)->Arg(3)->Unit(benchmark::kMicrosecond);

const bool kRegistered = [] {
  for (const std::string& name : st::WahbaSolver::names()) {
    benchmark::RegisterBenchmark(("wahba/" + name).c_str(), BM_Wahba, name)
        ->Arg(4)
        ->Arg(10)
        ->Arg(20)
        ->Unit(benchmark::kMicrosecond);
  }
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
