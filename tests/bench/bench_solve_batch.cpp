// `solve` on a batch (issue 15 item 5), in-process through the command's own code
// (app/solve/solve_run.hpp):
//   BM_BatchSolveTiffFrame  one of the eight 1024x768 16-bit TIFFs of tests/data/tetra3 per
//                           iteration: TIFF decoding, detection, identification (FOV given,
//                           --fov-deg 11.4), attitude; the run's one database already loaded.
//                           Target < 8 ms per frame on one core.
//   BM_DatabaseCacheHit     the in-memory database of those frames read back from the disk
//                           cache (what a second `solve` process pays). Target < 25 ms.
//   BM_InflightFrame        one of the 15 Swarm frames of 2014-11-17 (tests/data/swarm; 752x290
//                           8-bit PNG, rows binned 2x, radiation hits) per iteration, with its
//                           head's camera calibrated on the 2014-10-21 frames (`calibrate`,
//                           docs/inflight/): PNG decoding, detection with the hit rule,
//                           identification, attitude. Target <= 10 ms (issue 34).
//   BM_InflightFrameNominalCamera  the same with the nominal binned camera file
//                           (docs/inflight/swarm_str.yaml): its aspect is 4 % off, so most
//                           frames are solved by healing it (fx, fy searched and fitted).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

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

/// The November frames of the Swarm heads, each with the solver of its head.
void inflight(benchmark::State& state, bool calibrated) {
  log::setVerbosity(log::Verbosity::kQuiet);
  useOwnCache();
  std::vector<std::pair<std::string, const solve::PlateSolver*>> frames;
  std::vector<std::unique_ptr<solve::PlateSolver>> solvers;
  for (const char* head : {"A", "B", "C"}) {
    solve::SolveOptions o;
    o.no_aberration = true;
    o.camera.camera_file = test::repoDir() + "/docs/inflight/swarm_str" +
                           (calibrated ? std::string(1, char(head[0] + 32)) + "_calibrated" : "") +
                           ".yaml";
    solvers.push_back(std::make_unique<solve::PlateSolver>(o));
    for (const std::string& f : test::swarmFrames())
      if (f.find(std::string("SWA_Str") + head + "_2014-11-17") != std::string::npos)
        frames.emplace_back(f, solvers.back().get());
  }
  for (const auto& [f, solver] : frames) solver->solveFile(f);  // databases built, caches warm
  std::size_t k = 0, solved = 0;
  for (auto _ : state) {
    const auto& [path, solver] = frames[k++ % frames.size()];
    auto out = solver->solveFile(path);
    solved += out->code == 0;
    benchmark::DoNotOptimize(out);
  }
  state.counters["solved_fraction"] = double(solved) / double(k);
  state.counters["target_us"] = 10000;  // issue 34
}

void BM_InflightFrame(benchmark::State& state) { inflight(state, true); }
BENCHMARK(BM_InflightFrame)->Unit(benchmark::kMillisecond)->MinTime(2.0);

void BM_InflightFrameNominalCamera(benchmark::State& state) { inflight(state, false); }
BENCHMARK(BM_InflightFrameNominalCamera)->Unit(benchmark::kMillisecond)->MinTime(2.0);

}  // namespace
}  // namespace st

BENCHMARK_MAIN();
