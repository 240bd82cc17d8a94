// Ground-program benchmarks: database build (15 deg, V <= 6.5), k-vector pair range query,
// cone and rectangle (FOV) queries, database load.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <filesystem>
#include <random>

#include "catalog/star_catalog.hpp"
#include "catalog/star_database.hpp"
#include "common/conventions.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

const StarCatalog& catalog() {
  static const StarCatalog cat = loadCatalog(StarDatabase::defaultCatalogPath());
  return cat;
}

DatabaseParams params15() {
  DatabaseParams p{};
  p.max_pair_angle = deg2rad(15.0);
  p.mag_limit = 6.5;
  p.epoch_jyear = 2020.0;
  p.aberration = true;
  p.double_star_sep = arcsec2rad(10.0);
  p.neighbour_radius = deg2rad(7.5);
  return p;
}

const StarDatabase& db15() {
  static const StarDatabase db = StarDatabase::build(catalog(), params15());
  return db;
}

std::vector<Vec3> randomAxes(std::size_t n) {
  std::mt19937_64 rng(42);
  std::normal_distribution<double> g(0, 1);
  std::vector<Vec3> v(n);
  for (Vec3& a : v) a = Vec3(g(rng), g(rng), g(rng)).normalized();
  return v;
}

void BM_LoadHipparcosSubset(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(loadCatalog(StarDatabase::defaultCatalogPath()));
}
BENCHMARK(BM_LoadHipparcosSubset)->Unit(benchmark::kMillisecond);

// The acceptance target: build for a 15 deg FOV and V <= 6.5 under 2 s, file under 10 MB.
void BM_BuildDatabase15degV65(benchmark::State& state) {
  const StarCatalog& cat = catalog();
  std::size_t pairs = 0;
  for (auto _ : state) {
    const StarDatabase db = StarDatabase::build(cat, params15());
    pairs = db.pairs().size();
  }
  const std::string path = test::makeTempDir("bench_catalog") + "/db.stdb";
  db15().save(path);
  state.counters["stars"] = double(db15().stars().size());
  state.counters["pairs"] = double(pairs);
  state.counters["kvector"] = double(db15().pairKVector().size());
  state.counters["file_MB"] = double(std::filesystem::file_size(path)) / 1e6;
}
BENCHMARK(BM_BuildDatabase15degV65)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_LoadDatabase15degV65(benchmark::State& state) {
  const std::string path = test::makeTempDir("bench_catalog") + "/db.stdb";
  db15().save(path);
  for (auto _ : state) benchmark::DoNotOptimize(StarDatabase::load(path));
}
BENCHMARK(BM_LoadDatabase15degV65)->Unit(benchmark::kMillisecond);

// k-vector range query [theta - d, theta + d]; `state.range(0)` is d in arcsec. The time
// includes touching every match (sum of ids), reported as matches per query.
void BM_PairRangeQuery(benchmark::State& state) {
  const StarDatabase& db = db15();
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> th(deg2rad(0.5), deg2rad(14.5));
  std::vector<double> thetas(4096);
  for (double& t : thetas) t = th(rng);
  const double d = arcsec2rad(double(state.range(0)));
  std::size_t i = 0, matches = 0;
  uint64_t sink = 0;
  for (auto _ : state) {
    const double t = thetas[i++ & 4095];
    const PairSlice s = db.pairsInRange(t - d, t + d);
    for (const StarPair* p = s.begin; p != s.end; ++p) sink += p->a;
    matches += s.size();
  }
  benchmark::DoNotOptimize(sink);
  state.counters["matches"] = benchmark::Counter(double(matches), benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_PairRangeQuery)->Arg(0)->Arg(10)->Arg(60);

// Cone query of radius `state.range(0)` tenths of a degree.
void BM_ConeQuery(benchmark::State& state) {
  const StarDatabase& db = db15();
  const auto axes = randomAxes(4096);
  const double r = deg2rad(state.range(0) / 10.0);
  std::vector<uint32_t> out;
  out.reserve(4096);
  std::size_t i = 0, found = 0;
  for (auto _ : state) {
    db.coneQuery(axes[i++ & 4095], r, out);
    found += out.size();
  }
  state.counters["stars"] = benchmark::Counter(double(found), benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_ConeQuery)->Arg(10)->Arg(75)->Arg(106);

// FOV query: an 11.4 x 8.6 deg image rectangle (the tetra3 camera) at random attitudes.
void BM_RectangleQuery(benchmark::State& state) {
  const StarDatabase& db = db15();
  const auto axes = randomAxes(4096);
  std::vector<Quat> q(4096);
  for (std::size_t k = 0; k < q.size(); ++k) q[k] = quatExp(axes[k] * 2.0);
  const double tx = std::tan(deg2rad(5.7)), ty = std::tan(deg2rad(4.3));
  std::vector<uint32_t> out;
  out.reserve(4096);
  std::size_t i = 0, found = 0;
  for (auto _ : state) {
    db.rectangleQuery(q[i++ & 4095], tx, ty, out);
    found += out.size();
  }
  state.counters["stars"] = benchmark::Counter(double(found), benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_RectangleQuery);

}  // namespace
}  // namespace st

BENCHMARK_MAIN();
