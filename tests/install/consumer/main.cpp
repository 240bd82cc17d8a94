// Solves every image given on the command line with the installed public API, prints one
// JSON line per frame, and exits 0 only when all solved. With --bench N it also times N
// in-process solves of each frame already in memory (the C++ side of
// python/bench_solve.py). The first frame also goes through the per-frame Tracker twice:
// lost-in-space, then tracking on its own prediction.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <startracker/startracker.hpp>

int main(int argc, char** argv) {
  int bench = 0;
  std::vector<std::string> paths;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--bench" && i + 1 < argc)
      bench = std::atoi(argv[++i]);
    else
      paths.push_back(a);
  }
  if (paths.empty()) {
    std::fprintf(stderr, "usage: consumer [--bench N] IMAGE...\n");
    return 2;
  }
  st::api::SolveOptions o;
  o.fov_deg = 11.4;
  int solved = 0;
  for (const std::string& p : paths) {
    const st::api::SolveResult r = st::api::solveFile(p, o);
    std::printf("%s\n", r.json.dump().c_str());
    solved += r.solved;
    if (bench > 0) {
      // The same pixels and epoch as the file gives, in memory: what a flight program does.
      const cv::Mat img = cv::imread(p, cv::IMREAD_UNCHANGED);
      st::api::SolveOptions m = o;
      m.epoch_jyear = r.json.value("epoch_jyear", 0.0);
      st::api::solve(img, m);  // warm: the database is built once per camera
      const auto t0 = std::chrono::steady_clock::now();
      for (int k = 0; k < bench; ++k) st::api::solve(img, m);
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      std::printf("bench %s %.3f ms/frame\n", p.c_str(), ms / bench);
    }
  }
  const cv::Mat first = cv::imread(paths[0], cv::IMREAD_UNCHANGED);
  const st::CameraModel cam = st::CameraModel::fromFov(first.cols, first.rows, st::deg2rad(11.4));
  // The frames' epoch (2019-07-29, their file names): a database at today's would be off by
  // the stars' proper motion and the change of annual aberration.
  st::api::Tracker tracker(cam, {}, st::api::Database::forCamera(cam, 6.6, 2019.574));
  const st::FrameResult a = tracker.process(first, 0.0);
  const st::FrameResult b = tracker.process(first, 0.1);
  std::printf("tracker %s\n", st::api::frameResultJson(b).dump().c_str());
  const bool tracked = a.mode == st::StarTrackerMode::kLostInSpace &&
                       b.mode == st::StarTrackerMode::kTracking;
  std::printf("solved %d of %zu; tracker: %s then %s\n", solved, paths.size(), st::toString(a.mode),
              st::toString(b.mode));
  return solved == int(paths.size()) && tracked ? 0 : 1;
}
