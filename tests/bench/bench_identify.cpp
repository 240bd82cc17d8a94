// Lost-in-space identification benchmarks (issue 6):
//  - BM_IdentifyVerifyQuest20: pyramid + verification + QUEST from 20 centroids of which 3
//    are false stars (15 deg FOV, V <= 6.0, 0.1 px noise); target median < 50 us.
//  - BM_SolveRealFrame: detection + identification + QUEST on the real 1024x768 frame
//    Alt40_Azi-135 with its camera known (database built beforehand); target < 10 ms.
//  - BM_MonteCarlo10000: 10,000 random attitudes (the larger run), counters report
//    solved / wrong.
#include <benchmark/benchmark.h>

#include <opencv2/imgcodecs.hpp>

#include "common/conventions.hpp"
#include "sensors/detect/star_detector.hpp"
#include "sensors/identify/fov_search.hpp"
#include "sensors/identify/identifier.hpp"
#include "tests/identify/scene.hpp"

namespace st {
namespace {

std::vector<std::vector<StarObservation>> scenes20() {
  const StarDatabase& db = test::testDatabase();
  const CameraModel cam = test::testCamera(15.0);
  std::mt19937_64 rng(42);
  std::vector<std::vector<StarObservation>> out;
  test::SceneParams sp;
  sp.false_min = sp.false_max = 0;
  sp.drop_fraction = 0;
  while (out.size() < 200) {
    test::Scene sc = test::makeScene(rng, db, cam, sp, test::randomAttitude(rng));
    if (sc.centroids.size() < 17) continue;
    std::vector<Centroid> c(sc.centroids.begin(), sc.centroids.begin() + 17);
    std::uniform_real_distribution<double> u01;
    for (int f = 0; f < 3; ++f) {  // false stars at random places in the brightness order
      Centroid s;
      s.px = Vec2(u01(rng) * 1023, u01(rng) * 1023);
      s.cov_px = 0.01 * Mat2::Identity();
      c.insert(c.begin() + static_cast<long>(u01(rng) * c.size()), s);
    }
    out.push_back(toStarObservations(c, cam));
  }
  return out;
}

void BM_IdentifyVerifyQuest20(benchmark::State& state) {
  const StarDatabase& db = test::testDatabase();
  const CameraModel cam = test::testCamera(15.0);
  static const auto scenes = scenes20();
  auto id = StarIdentifier::create("pyramid");
  std::size_t k = 0, solved = 0, runs = 0;
  for (auto _ : state) {
    const IdentifyResult r = id->identify(scenes[k], db, cam);
    benchmark::DoNotOptimize(r.q_ic);
    solved += r.solved();
    ++runs;
    k = (k + 1) % scenes.size();
  }
  state.counters["solved_fraction"] = double(solved) / double(runs);
}
BENCHMARK(BM_IdentifyVerifyQuest20)
    ->Unit(benchmark::kMicrosecond)
    ->Repetitions(5)
    ->ReportAggregatesOnly(true);

void BM_SolveRealFrame(benchmark::State& state) {
  const std::string path =
      test::tetra3ImageDir() + "/2019-07-29T204726_Alt40_Azi-135_Try1.tiff";
  const cv::Mat img = cv::imread(path, cv::IMREAD_ANYDEPTH | cv::IMREAD_GRAYSCALE);
  if (img.empty()) {
    state.SkipWithError("cannot read the tetra3 frame");
    return;
  }
  const CameraModel cam = CameraModel::fromFov(img.cols, img.rows, deg2rad(11.424));
  static const StarDatabase db = [&] {
    DatabaseParams p{};
    p.max_pair_angle = 2 * cam.halfDiagonalFov() + deg2rad(0.2);
    p.mag_limit = 7.0;
    p.epoch_jyear = 2019.57;
    p.double_star_sep = arcsec2rad(60.0);
    p.neighbour_radius = cam.halfDiagonalFov();
    return StarDatabase::build(loadCatalog(test::hipparcosSubsetPath()), p);
  }();
  auto id = StarIdentifier::create("pyramid");
  std::size_t solved = 0, runs = 0;
  for (auto _ : state) {
    const DetectionResult det = detectStars(img);
    const FovSearchResult r = identifyAndFit(det.stars, cam, db, *id, CameraFitPolicy::fixed(), 0.5);
    benchmark::DoNotOptimize(r.result.q_ic);
    solved += r.result.solved();
    ++runs;
  }
  state.counters["solved_fraction"] = double(solved) / double(runs);
}
BENCHMARK(BM_SolveRealFrame)->Unit(benchmark::kMillisecond);

void BM_MonteCarlo10000(benchmark::State& state) {
  const StarDatabase& db = test::testDatabase();
  const CameraModel cam = test::testCamera(15.0);
  auto id = StarIdentifier::create("pyramid");
  for (auto _ : state) {
    std::mt19937_64 rng(12345);
    int solved = 0, wrong = 0;
    for (int k = 0; k < 10000; ++k) {
      const test::Scene sc = test::makeScene(rng, db, cam, {}, test::randomAttitude(rng));
      const IdentifyResult r = id->identify(toStarObservations(sc.centroids, cam), db, cam);
      if (!r.solved()) continue;
      bool ok = attitudeNees(r.q_ic, r.cov_cam, sc.q_ib) < 40.0;
      for (const StarMatch& m : r.matches)
        ok = ok && sc.truth[m.obs_index] == static_cast<int>(m.star_index);
      ok ? ++solved : ++wrong;
    }
    state.counters["solved"] = solved;
    state.counters["wrong"] = wrong;
  }
}
BENCHMARK(BM_MonteCarlo10000)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
}  // namespace st

BENCHMARK_MAIN();
