// `solve` on a batch (issue 15 item 5), in-process through the command's own code
// (app/solve/solve_run.hpp):
//   BM_BatchSolveTiffFrame  one of the eight 1024x768 16-bit TIFFs of tests/data/tetra3 per
//                           iteration: TIFF decoding, detection, identification (FOV given,
//                           --fov-deg 11.4), attitude; the run's one database already loaded.
//                           Target < 8 ms per frame on one core.
//   BM_DatabaseCacheHit     the in-memory database of those frames read back from the disk
//                           cache (what a second `solve` process pays). Target < 25 ms.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "catalog/database_cache.hpp"
#include "solve/plate_solver.hpp"
#include "catalog/database_recipe.hpp"
#include "common/conventions.hpp"
#include "common/log.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

/// A cache folder of the benchmark's own.
void useOwnCache() {
  static const std::string dir = test::makeTempDir("bench_cache");
  ::setenv("XDG_CACHE_HOME", dir.c_str(), 1);
}

void BM_BatchSolveTiffFrame(benchmark::State& state) {
  log::setVerbosity(log::Verbosity::kQuiet);
  useOwnCache();
  const auto frames = test::tetra3Frames();
  solve::SolveOptions o;
  o.camera.fov_deg = 11.4;
  const solve::PlateSolver solver(o);
  std::size_t k = 0, solved = 0;
  for (auto _ : state) {
    auto f = solver.solveFile(frames[k++ % frames.size()]);
    solved += f->code == 0;
    benchmark::DoNotOptimize(f);
  }
  state.counters["solved_fraction"] = double(solved) / double(k);
  state.counters["target_us"] = 8000;  // issue 15
}
BENCHMARK(BM_BatchSolveTiffFrame)->Unit(benchmark::kMillisecond)->MinTime(2.0);

void BM_DatabaseCacheHit(benchmark::State& state) {
  log::setVerbosity(log::Verbosity::kQuiet);
  useOwnCache();
  // The recipe solve uses for these frames (1024x768, --fov-deg 11.4).
  const CameraModel cam = CameraModel::fromFov(1024, 768, deg2rad(11.4));
  CameraDatabaseRecipe r;
  r.diagonal_fov_rad = 2 * cam.halfDiagonalFov();
  r.pixel_scale_rad = cam.pixelScale();
  r.mag_limit = 6.6;
  r.epoch_jyear = 2019.574;
  const DatabaseParams p = databaseParams(r);
  DatabaseCache(StarDatabase::defaultCatalogPath(), true).get(p);  // written once
  for (auto _ : state) {
    DatabaseCache cache(StarDatabase::defaultCatalogPath(), true);  // nothing in memory
    auto c = cache.get(p);
    if (c.how.rfind("read from the cache", 0) != 0) state.SkipWithError(c.how.c_str());
    benchmark::DoNotOptimize(c);
  }
  state.counters["target_us"] = 25000;  // issue 15
}
BENCHMARK(BM_DatabaseCacheHit)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace st

BENCHMARK_MAIN();
