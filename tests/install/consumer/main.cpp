// Solves every image given on the command line with the installed public API, prints one
// JSON line per frame, and exits 0 only when all solved. With --bench N it also times N
// in-process solves of each frame already in memory (the C++ side of
// python/bench/bench_solve.py). The first frame also goes through the per-frame Tracker twice:
// lost-in-space, then tracking with a (zero) gyro rate.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
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
    if (r.solved)
      std::printf("%s: RA %.4f Dec %.4f roll %.4f deg, %d stars, %.1f ms\n", p.c_str(), r.ra_deg,
                  r.dec_deg, r.roll_deg, r.json["stars_matched"].get<int>(),
                  r.json["timing_ms"]["total"].get<double>());
    else
      std::printf("%s\n", r.json.dump().c_str());
    solved += r.solved;
    if (bench > 0) {
      // The same pixels and epoch as the file gives, in memory: what a flight program does.
      const cv::Mat img = cv::imread(p, cv::IMREAD_UNCHANGED);
      st::api::SolveOptions m = o;
      m.epoch_jyear = r.json.value("epoch_jyear", 0.0);
      st::api::solve(img, m);  // warm: the database is built once per camera
      double sum = 0, best = 1e300;
      for (int k = 0; k < bench; ++k) {
        const auto t0 = std::chrono::steady_clock::now();
        st::api::solve(img, m);
        const double ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        sum += ms;
        best = std::min(best, ms);
      }
      std::printf("bench %s mean %.3f min %.3f ms/frame\n", p.c_str(), sum / bench, best);
    }
  }
  // The tracker on the first frame's camera as solve fitted it (its FOV), at the frames'
  // epoch. No calibration file: lens distortion leaves ~0.2 px RMS residuals, so the
  // centroid sigma floors are solve's for such a camera (0.5 px), not the simulator's.
  const cv::Mat first = cv::imread(paths[0], cv::IMREAD_UNCHANGED);
  const st::api::SolveResult s0 = st::api::solveFile(paths[0], o);
  const st::CameraModel cam = st::CameraModel::fromFov(
      first.cols, first.rows, st::deg2rad(s0.json.value("hfov_deg", 11.4)));
  st::api::TrackerSettings to;
  to.min_sigma_px = to.tracking_min_sigma_px = 0.5;
  st::api::Tracker tracker(
      cam, to, st::api::Database::forCamera(cam, 6.6, s0.json.value("epoch_jyear", 0.0)));
  const st::FrameResult a = tracker.process(first, 0.0);
  st::FrameInputs gyro;  // a gyro says the camera stood still: the tracker predicts from it
  gyro.rate_body = st::Vec3::Zero();
  // The next frame of a camera standing still: the same sky, the bias 1 ADU higher (the same
  // image again would be refused as a frozen readout).
  cv::Mat next;
  cv::add(first, cv::Scalar(1), next);
  const st::FrameResult b = tracker.process(next, 0.1, gyro);
  std::printf("tracker %s\n", st::api::frameResultJson(b).dump().c_str());
  const bool tracked = a.mode == st::StarTrackerMode::kLostInSpace &&
                       b.mode == st::StarTrackerMode::kTracking;
  std::printf("solved %d of %zu, tracker: %s then %s\n", solved, paths.size(), st::toString(a.mode),
              st::toString(b.mode));
  return solved == int(paths.size()) && tracked ? 0 : 1;
}
