// Speed of detection + centroiding on one core: the real 1024x768 16-bit frames, a 2048x1536
// frame (a real frame upscaled 2x), and 20 predictive windows.
#include <benchmark/benchmark.h>

#include <filesystem>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "sensors/detect/star_detector.hpp"
#include "tests/support/test_paths.hpp"

namespace {

const std::vector<cv::Mat>& frames() {
  static const std::vector<cv::Mat> f = [] {
    std::vector<std::string> paths;
    for (const auto& e : std::filesystem::directory_iterator(st::test::tetra3ImageDir()))
      if (e.path().extension() == ".tiff") paths.push_back(e.path().string());
    std::sort(paths.begin(), paths.end());
    std::vector<cv::Mat> out;
    for (const auto& p : paths) out.push_back(cv::imread(p, cv::IMREAD_UNCHANGED));
    return out;
  }();
  return f;
}

void BM_DetectReal1024x768(benchmark::State& state, std::string centroider) {
  cv::setNumThreads(1);
  st::DetectorOptions o;
  o.centroider = centroider;
  std::size_t k = 0, stars = 0;
  for (auto _ : state) {
    const auto r = st::detectStars(frames()[k++ % frames().size()], o);
    stars += r.stars.size();
    benchmark::DoNotOptimize(r);
  }
  state.counters["stars"] = static_cast<double>(stars) / static_cast<double>(state.iterations());
}
BENCHMARK_CAPTURE(BM_DetectReal1024x768, gauss, std::string("gauss"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_DetectReal1024x768, iwc, std::string("iwc"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_DetectReal1024x768, cog, std::string("cog"))->Unit(benchmark::kMillisecond);

void BM_Detect2048x1536(benchmark::State& state) {
  cv::setNumThreads(1);
  cv::Mat big;
  cv::resize(frames()[0], big, cv::Size(2048, 1536), 0, 0, cv::INTER_LINEAR);
  std::size_t stars = 0;
  for (auto _ : state) {
    const auto r = st::detectStars(big);
    stars += r.stars.size();
    benchmark::DoNotOptimize(r);
  }
  state.counters["stars"] = static_cast<double>(stars) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_Detect2048x1536)->Unit(benchmark::kMillisecond);

void BM_Windows20(benchmark::State& state) {
  cv::setNumThreads(1);
  const cv::Mat& img = frames()[0];
  st::DetectorOptions o;
  o.max_stars = 20;
  std::vector<st::PredictedStar> pred;
  for (const auto& s : st::detectStars(img, o).stars)
    pred.push_back({s.px + st::Vec2(0.7, -0.5), st::Mat2::Identity() * 1.0, st::Vec2::Zero()});
  std::size_t found = 0;
  for (auto _ : state) {
    const auto r = st::centroidWindows(img, pred);
    for (const auto& w : r) found += w.centroid.has_value();
    benchmark::DoNotOptimize(r);
  }
  state.counters["windows"] = static_cast<double>(pred.size());
  state.counters["found"] = static_cast<double>(found) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_Windows20)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
