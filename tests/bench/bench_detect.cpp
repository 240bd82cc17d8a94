// Speed of detection + centroiding on ONE core (cv::setNumThreads(1) before anything runs;
// run pinned: `taskset -c 0 bench_detect`): each of the eight real 1024x768 16-bit tetra3
// frames (per-frame times, the target is on every frame), all eight in turn for each
// centroider, a 2048x1536 frame (a real frame upscaled 2x), and 20 predictive windows; the
// "_detector" variants reuse one StarDetector (per-frame code) instead of the free functions.
// Targets of issue 5 in the `target_us` counter (read by scripts/benchmarks_to_md.py).
#include <benchmark/benchmark.h>

#include <filesystem>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "sensors/detect/star_detector.hpp"
#include "tests/support/test_paths.hpp"

namespace {

constexpr double kTargetFrameUs = 3000;  // 1024x768 full-frame detection + centroiding
constexpr double kTargetBigUs = 10000;   // 2048x1536
constexpr double kTargetWindowsUs = 50;  // 20 predictive windows

std::vector<std::string> framePaths() {
  std::vector<std::string> paths;
  for (const auto& e : std::filesystem::directory_iterator(st::test::tetra3ImageDir()))
    if (e.path().extension() == ".tiff") paths.push_back(e.path().string());
  std::sort(paths.begin(), paths.end());
  return paths;
}

const std::vector<cv::Mat>& frames() {
  static const std::vector<cv::Mat> f = [] {
    std::vector<cv::Mat> out;
    for (const auto& p : framePaths()) out.push_back(cv::imread(p, cv::IMREAD_UNCHANGED));
    return out;
  }();
  return f;
}

void BM_DetectRealFrame(benchmark::State& state) {
  const cv::Mat& img = frames()[static_cast<std::size_t>(state.range(0))];
  std::size_t stars = 0;
  for (auto _ : state) {
    const auto r = st::detectStars(img);
    stars += r.stars.size();
    benchmark::DoNotOptimize(r);
  }
  state.counters["stars"] = static_cast<double>(stars) / static_cast<double>(state.iterations());
  state.counters["target_us"] = kTargetFrameUs;
}
BENCHMARK(BM_DetectRealFrame)->DenseRange(0, 7)->Unit(benchmark::kMillisecond);

// `detector`: one StarDetector built before the loop and one result reused (what per-frame
// code does: no validation, centroider creation or result allocation per call) instead of
// the one-shot detectStars().
void BM_DetectReal1024x768(benchmark::State& state, std::string centroider, bool detector) {
  st::DetectorOptions o;
  o.centroider = centroider;
  st::StarDetector det(o);
  st::DetectionResult r;  // reused by the detector: its star vector keeps its capacity
  std::size_t k = 0, stars = 0;
  for (auto _ : state) {
    const cv::Mat& img = frames()[k++ % frames().size()];
    if (detector)
      det.detect(img, r);
    else
      r = st::detectStars(img, o);
    stars += r.stars.size();
    benchmark::DoNotOptimize(r);
  }
  state.counters["stars"] = static_cast<double>(stars) / static_cast<double>(state.iterations());
  state.counters["target_us"] = kTargetFrameUs;
}
BENCHMARK_CAPTURE(BM_DetectReal1024x768, gauss, std::string("gauss"), false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_DetectReal1024x768, iwc, std::string("iwc"), false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_DetectReal1024x768, cog, std::string("cog"), false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_DetectReal1024x768, gauss_detector, std::string("gauss"), true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_DetectReal1024x768, cog_detector, std::string("cog"), true)->Unit(benchmark::kMillisecond);

void BM_Detect2048x1536(benchmark::State& state) {
  cv::Mat big;
  cv::resize(frames()[0], big, cv::Size(2048, 1536), 0, 0, cv::INTER_LINEAR);
  std::size_t stars = 0;
  for (auto _ : state) {
    const auto r = st::detectStars(big);
    stars += r.stars.size();
    benchmark::DoNotOptimize(r);
  }
  state.counters["stars"] = static_cast<double>(stars) / static_cast<double>(state.iterations());
  state.counters["target_us"] = kTargetBigUs;
}
BENCHMARK(BM_Detect2048x1536)->Unit(benchmark::kMillisecond);

// Tracking: the 20 brightest stars of a real frame predicted 0.7 px off with a 1 px sigma.
// `detector`: one StarDetector and one result vector reused, instead of centroidWindows().
void BM_Windows20(benchmark::State& state, std::string centroider, bool detector) {
  const cv::Mat& img = frames()[0];
  st::DetectorOptions o;
  o.max_stars = 20;
  std::vector<st::PredictedStar> pred;
  for (const auto& s : st::detectStars(img, o).stars)
    pred.push_back({s.px + st::Vec2(0.7, -0.5), st::Mat2::Identity() * 1.0, st::Vec2::Zero()});
  o = {};
  o.centroider = centroider;
  st::StarDetector det(o);
  std::vector<st::WindowResult> r;
  std::size_t found = 0;
  for (auto _ : state) {
    if (detector)
      det.centroidWindows(img, pred, r);
    else
      r = st::centroidWindows(img, pred, o);
    for (const auto& w : r) found += w.centroid.has_value();
    benchmark::DoNotOptimize(r);
  }
  state.counters["windows"] = static_cast<double>(pred.size());
  state.counters["found"] = static_cast<double>(found) / static_cast<double>(state.iterations());
  state.counters["target_us"] = kTargetWindowsUs;
}
BENCHMARK_CAPTURE(BM_Windows20, gauss, std::string("gauss"), false)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Windows20, iwc, std::string("iwc"), false)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Windows20, cog, std::string("cog"), false)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Windows20, gauss_detector, std::string("gauss"), true)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Windows20, iwc_detector, std::string("iwc"), true)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Windows20, cog_detector, std::string("cog"), true)->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
  cv::setNumThreads(1);  // the targets are for one core: no OpenCV worker threads
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
