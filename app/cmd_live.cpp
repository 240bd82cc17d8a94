// `startracker live CONFIG.ini`: the live sensor app, rawlog-grabber style. Every .ini
// section with `driver = <CGenericSensor class>` is a sensor run in its own thread
// (app/live/sensor_runner.hpp); the main loop takes their observations, records EVERY one to
// the rawlog as it arrives (in timestamp order within each batch), and runs the filter in
// real time whose prediction goes back to each CStarTrackerSensor (app/live/live_filter.hpp).
// SIGINT / SIGTERM end the run cleanly: sensors stopped, what they delivered written, rawlog
// closed, summary printed.
//
// Optional sections without a driver:
//   [global]     rawlog_file = out.rawlog (default live.rawlog; -o wins)
//   [navigator]  enabled = true, latency_s = 0.5, arw_deg_rt_h = 0.15, rrw_deg_h_rt_h = 0.5,
//                bias_sigma_deg_h = 10, reinit_after_rejections = 3
// Relative paths inside the .ini are relative to the .ini's folder (the sensors are
// configured from there).
#include <mrpt/config/CConfigFile.h>
#include <mrpt/obs/CObservationImage.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <map>

#include "app/command.hpp"
#include "app/live/live_display.hpp"
#include "app/live/live_filter.hpp"
#include "app/live/sensor_runner.hpp"
#include "common/errors.hpp"
#include "sensors/mrpt/rawlog_io.hpp"
#include "sensors/mrpt/star_tracker_sensor.hpp"
#include "sensors/sim/simulated_sensors.hpp"

namespace st::app {

namespace {

namespace fs = std::filesystem;

volatile std::sig_atomic_t g_signal = 0;
extern "C" void onStopSignal(int sig) { g_signal = sig; }

struct LiveArgs {
  std::string config, out;
  double duration_s = 0;
  bool gui = false;
};

LiveFilterOptions filterOptions(const mrpt::config::CConfigFileBase& cfg, bool* enabled) {
  const std::string s = "navigator";
  LiveFilterOptions o;
  *enabled = cfg.read_bool(s, "enabled", true);
  o.latency_s = cfg.read_double(s, "latency_s", o.latency_s);
  o.reinit_after_rejections = cfg.read_int(s, "reinit_after_rejections", o.reinit_after_rejections);
  o.mekf = MekfOptions::fromDatasheet(cfg.read_double(s, "arw_deg_rt_h", 0.15),
                                      cfg.read_double(s, "rrw_deg_h_rt_h", 0.5),
                                      cfg.read_double(s, "bias_sigma_deg_h", 10.0));
  std::string err;
  if (!o.mekf.isValid(&err)) throw InputError("section 'navigator': " + err);
  if (!(o.latency_s >= 0)) throw InputError("section 'navigator' key 'latency_s': must be >= 0");
  return o;
}

int runLive(const LiveArgs& args) {
  registerStarTrackerClasses();
  registerSimulatedSensors();
  std::error_code ec;
  if (!fs::is_regular_file(args.config, ec))
    throw InputError("live config '" + args.config + "': no such file");
  const fs::path config = fs::absolute(args.config);
  mrpt::config::CConfigFile cfg(config.string());

  std::string out = args.out;
  if (out.empty()) out = cfg.read_string("global", "rawlog_file", "live.rawlog");
  // -o is relative to where the user runs; rawlog_file to the .ini, like every other path.
  const fs::path out_path = args.out.empty() ? config.parent_path() / out : fs::absolute(out);

  fs::current_path(config.parent_path());  // the .ini's relative paths
  bool nav_enabled = true;
  LiveFilter filter(filterOptions(cfg, &nav_enabled));
  std::vector<SensorSpec> specs = createSensors(cfg, args.config);  // InputError -> exit 2

  RawlogWriter writer(out_path.string());
  ObservationQueue queue;
  std::vector<std::unique_ptr<SensorRunner>> runners;
  std::vector<CStarTrackerSensor*> trackers;
  for (auto& spec : specs) {
    spec.sensor->setPathForExternalImages(writer.imagesDir());
    if (auto* t = dynamic_cast<CStarTrackerSensor*>(spec.sensor.get())) {
      trackers.push_back(t);
      if (nav_enabled) t->setInputsProvider([&filter](mrpt::Clock::time_point when) {
        FrameInputs in;
        in.prediction = filter.predict(when);
        return in;
      });
    }
    runners.push_back(std::make_unique<SensorRunner>(std::move(spec), queue));
  }

  g_signal = 0;
  struct sigaction sa {};
  sa.sa_handler = onStopSignal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);

  std::printf("live: %zu sensor(s) from %s, recording to %s\n", runners.size(),
              args.config.c_str(), out_path.string().c_str());
  std::fflush(stdout);
  for (auto& r : runners) r->start();
  for (auto& r : runners) r->waitInitialized();
  auto printReports = [&] {
    for (const auto& m : queue.takeReports()) std::fprintf(stderr, "live: %s\n", m.c_str());
  };
  int running = 0;
  for (auto& r : runners) {
    if (r->state() != SensorRunner::State::kFailed) ++running;
  }
  for (auto& r : runners) r->go();
  printReports();

  LiveDisplay display;
  if (args.gui) {
    std::string why;
    if (!display.open("startracker live", &why))
      std::fprintf(stderr, "live: --gui: %s; running without a window\n", why.c_str());
  }

  std::map<std::string, std::size_t> per_label;
  std::map<std::string, int> failures;  // reason -> frames
  int frames = 0, solved = 0, tracking = 0, lis = 0, image_no = 0;
  std::size_t written = 0;
  auto record = [&](std::vector<mrpt::obs::CObservation::Ptr> batch) {
    std::stable_sort(batch.begin(), batch.end(),
                     [](const auto& a, const auto& b) { return a->timestamp < b->timestamp; });
    for (auto& o : batch) {
      if (auto img = std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(o)) {
        if (!img->image.isExternallyStored()) {  // a sensor that keeps images inline
          char name[128];
          std::snprintf(name, sizeof(name), "%s_live_%06d.png", img->sensorLabel.c_str(),
                        image_no++);
          writer.externalizeImage(img->image, name);
        }
      }
      writer.write(*o);
      ++written;
      ++per_label[o->sensorLabel];
      if (auto f = std::dynamic_pointer_cast<CObservationStarTracker>(o)) {
        ++frames;
        if (f->hasAttitude()) ++solved;
        if (f->mode == StarTrackerMode::kTracking) ++tracking;
        if (f->mode == StarTrackerMode::kLostInSpace) ++lis;
        if (!f->hasAttitude()) ++failures[f->reason.substr(0, 80)];
      }
      if (nav_enabled) filter.push(o);
    }
  };

  using clock = std::chrono::steady_clock;
  const auto t_start = clock::now();
  auto last_gui = t_start;
  std::string why_stop = "all sensors stopped";
  if (running == 0) why_stop = "no sensor started";
  while (running > 0) {
    if (g_signal) {
      why_stop = g_signal == SIGINT ? "SIGINT" : "SIGTERM";
      break;
    }
    const double elapsed = std::chrono::duration<double>(clock::now() - t_start).count();
    if (args.duration_s > 0 && elapsed >= args.duration_s) {
      why_stop = "--duration";
      break;
    }
    record(queue.takeAll(0.05));
    if (nav_enabled) filter.processUpTo(mrpt::Clock::now());
    printReports();
    if (display.isOpen() && clock::now() - last_gui > std::chrono::milliseconds(100)) {
      last_gui = clock::now();
      if (!trackers.empty()) {
        Quat q;
        Mat3 P;
        std::optional<Quat> att;
        if (filter.current(q, P)) att = q;
        const auto fix = trackers.front()->lastObservation();
        display.show(trackers.front()->lastImage(), fix.get(), att);
      }
      if (display.quitRequested()) {
        why_stop = "the window (q)";
        break;
      }
    }
    int alive = 0;
    for (auto& r : runners) alive += r->state() != SensorRunner::State::kFailed;
    if (alive == 0) break;
  }
  const double elapsed = std::chrono::duration<double>(clock::now() - t_start).count();

  // Stop the sensors first, then write what they had already delivered: nothing received is
  // lost, and the rawlog is closed properly.
  for (auto& r : runners) r->stop();
  record(queue.takeAll(0.0));
  printReports();
  if (nav_enabled) filter.flush();
  writer.close();
  display.close();

  std::printf("live: stopped by %s after %.1f s\n", why_stop.c_str(), elapsed);
  std::printf("rawlog: %s, %zu observations\n", out_path.string().c_str(), written);
  for (const auto& [label, n] : per_label) std::printf("  %-16s %zu\n", label.c_str(), n);
  for (auto& r : runners) {
    const char* st = r->state() == SensorRunner::State::kFailed ? "FAILED" : "ok";
    std::printf("sensor '%s' %s: %zu observations, %s\n", r->section().c_str(),
                r->driver().c_str(), r->observations(), st);
  }
  const auto pct = [](int a, int b) { return b > 0 ? 100.0 * a / b : 0.0; };
  std::printf("star tracker: %d frames, %d solved (%.1f %%), %d tracking (%.1f %%), "
              "%d lost-in-space\n",
              frames, solved, pct(solved, frames), tracking, pct(tracking, frames), lis);
  for (const auto& [reason, n] : failures)
    std::printf("  failed %d x: %s\n", n, reason.c_str());
  if (nav_enabled) {
    const auto s = filter.stats();
    std::printf("filter: %d gyro samples, %d fixes (%d accepted, %d rejected, %d late, "
                "%d re-initialisations)\n",
                s.gyro, s.fixes, s.accepted, s.rejected, s.late, s.reinits);
  }
  std::fflush(stdout);
  return running > 0 ? kExitOk : kExitFailure;
}

}  // namespace

void addLiveCommand(CLI::App& root, CommandRun& run) {
  auto* cmd = root.add_subcommand(
      "live",
      "Run sensors from an .ini in real time (rawlog-grabber style): star tracker, gyro, "
      "cameras, simulated ones; the filter feeds predictions back to the star tracker; every "
      "observation is recorded to a rawlog. Ctrl-C / SIGTERM stop cleanly.");
  auto args = std::make_shared<LiveArgs>();
  cmd->add_option("config", args->config, "Sensors .ini (sections with driver = <class>)")
      ->required();
  cmd->add_option("-o,--output", args->out, "Output rawlog (default [global] rawlog_file)");
  cmd->add_option("--duration", args->duration_s, "Stop after this many seconds (0 = until "
                                                  "Ctrl-C / SIGTERM)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--gui", args->gui, "Show the frame, blobs, identified stars and attitude");
  cmd->callback([args, &run] { run = [args] { return runLive(*args); }; });
}

}  // namespace st::app
