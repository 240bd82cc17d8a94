// `startracker live CONFIG.ini`: the live sensor app, rawlog-grabber style. Every .ini
// section with `driver = <CGenericSensor class>` is a sensor run in its own thread
// (app/live/sensor_runner.hpp); the main loop takes their observations, records EVERY one to
// the rawlog in timestamp order (app/live/live_recorder.hpp), and runs the filter in real
// time whose prediction goes back to the CStarTrackerSensor on replay's schedule
// (app/live/live_navigator.hpp).
// SIGINT / SIGTERM end the run cleanly: sensors stopped, what they delivered written, rawlog
// closed, summary printed.
// SIGKILL loses at most the last ~0.8 s: the recorder flushes the rawlog every 0.25 s
// (app/live/live_recorder.hpp; tests/app/test_live_kill.cpp).
//
// Threading model (checked with ThreadSanitizer: scripts/tsan.sh):
//  - one thread per sensor (SensorRunner): it alone calls its sensor's initialize(),
//    doProcess() and getObservations(); it hands every observation to the ObservationQueue
//    (mutex + condition variable) and failures as report strings. Its state, counters and
//    stop/go flags are atomics; go/stop/initialised are signalled under the runner's mutex.
//  - the main thread (LiveSession) owns the queue's consumer side, the LiveRecorder and the
//    RawlogWriter (only it writes the file, the images of sensors that keep them inline and the
//    counts), the window and the summary. It creates the sensors before their threads start
//    and stops (joins) them before reading anything else from them.
//  - the LiveNavigator (the filter) is shared: the main thread pushes every batch into it,
//    the star tracker's thread asks it for each frame's prediction (frameInputs(), which may
//    wait on its condition variable for the gyro), and the window reads the estimate. One
//    mutex inside it serialises all of these.
//  - CStarTrackerSensor keeps its last fix and image under its own mutex for the window; it
//    calls the navigator without holding it (no lock order between the two).
//  - the simulated sensors share one start time (a mutex in simulated_sensors.cpp).
//  - the signal handler only stores the signal number (sig_atomic_t); the main loop polls it.
// Queues: ObservationQueue (sensors -> main, unbounded but emptied every 50 ms), the
// recorder's hold (0.5 s of observations) and the navigator's reorder window (0.5 s).
//
// Optional sections without a driver:
//   [global]     rawlog_file = out.rawlog (default live.rawlog; -o wins). Relative to the
//                working directory, as -o: an output never lands in the .ini's folder (the
//                repository's rawlogs/ for the samples); the path is printed.
//   [filter]     as in tracker.ini (navigation/tracker_ini.hpp): gyro datasheet numbers,
//                gate, update = attitude | stars
//   [navigator]  as in tracker.ini, plus enabled = true; reorder_window_s (default 0.5 here)
//                is the latency a star-tracker fix may have and still enter the filter
// All three are strict schemas (unknown keys exit 2), printed by `startracker config`.
// The filter is the one fusion loop of `replay` (app/live/live_navigator.hpp).
// Relative input paths inside the .ini are relative to the .ini's folder (the sensors are
// configured from there). Every output path is checked before the sensors start.
// Beside the rawlog, `<stem>_tracker.ini` (app/live/replay_config.hpp) holds the tracker and
// filter of the run: `startracker replay RAWLOG --config <stem>_tracker.ini` makes the same
// fixes from the recorded frames, since the tracker asks the loop on replay's schedule
// (app/live/live_navigator.hpp).
#include <mrpt/config/CConfigFile.h>
#include <mrpt/obs/CObservationImage.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <map>

#include "app/cli/common_flags.hpp"
#include "app/command.hpp"
#include "app/earlier_run.hpp"
#include "app/live/integrity_summary.hpp"
#include "app/live/live_display.hpp"
#include "app/live/live_navigator.hpp"
#include "app/live/live_recorder.hpp"
#include "app/live/replay_config.hpp"
#include "app/live/sensor_runner.hpp"
#include "common/output_file.hpp"
#include "common/stop_signal.hpp"
#include "common/errors.hpp"
#include "common/log.hpp"
#include "config/ini_reader.hpp"
#include "navigation/run_summary.hpp"
#include "navigation/tracker_config.hpp"
#include "sensors/mrpt/rawlog_io.hpp"
#include "sensors/mrpt/star_tracker_sensor.hpp"
#include "sensors/sim/simulated_sensors.hpp"

namespace st::app {

namespace {

namespace fs = std::filesystem;


struct LiveArgs {
  std::string config, out, csv;  // out and csv: absolute once checked
  double duration_s = 0;
  bool gui = false, force = false;
};

/// One live run: the sensors in their threads, the recorder, the navigator, the window.
class LiveSession {
 public:
  LiveSession(const LiveArgs& args, const mrpt::config::CConfigFileBase& cfg,
              const fs::path& out_path)
      : args_(args), out_path_(out_path) {
    bool nav_enabled = true;
    nav_opts_ = liveNavigatorOptions(cfg, args.config, &nav_enabled);
    nav_enabled_ = nav_enabled;
    live_keys_ = readLiveIni(IniReader{cfg, args.config});
    std::vector<SensorSpec> specs = createSensors(cfg, args.config);  // InputError -> exit 2
    // The recording is opened (and an earlier one replaced) only once the configuration
    // is known good: a run refused on its .ini leaves nothing behind.
    replaceEarlierRun(out_path.string(), args.force);
    writer_ = std::make_unique<RawlogWriter>(out_path.string());
    recorder_ = std::make_unique<LiveRecorder>(*writer_, nullptr);
    recorder_->writeMarker(*recordingMarker(kRecordingStartLabel,
                                            "startracker live recording from " + args.config +
                                                "; it ends with a " + kRecordingEndLabel +
                                                " comment unless it was cut"));  // no time
    for (auto& spec : specs) {
      spec.sensor->setPathForExternalImages(writer_->imagesDir());
      if (auto* t = dynamic_cast<CStarTrackerSensor*>(spec.sensor.get())) trackers_.push_back(t);
      runners_.push_back(std::make_unique<SensorRunner>(std::move(spec), queue_));
    }
    if (nav_enabled_ && !trackers_.empty()) orderHeads();  // before any sensor starts
  }

  /// True when every sensor failed to start on its configuration (exit 2, not 1).
  bool allFailedOnInput() const {
    return std::all_of(runners_.begin(), runners_.end(),
                       [](const auto& r) { return r->failedOnInput(); });
  }

  /// Starts the sensors and the navigator; returns how many sensors started.
  int start() {
    std::printf("live: %zu sensor(s) from %s, recording to %s\n", runners_.size(),
                args_.config.c_str(), out_path_.string().c_str());
    std::fflush(stdout);
    for (auto& r : runners_) r->start();
    for (auto& r : runners_) r->waitInitialized();
    // The navigator needs the star tracker's database and camera: built by initialize().
    if (nav_enabled_ && !trackers_.empty() && trackers_.front()->database()) {
      CStarTrackerSensor* t = trackers_.front();
      NavigatorOptions o = nav_opts_;
      o.star_tracker_label = t->getSensorLabel();
      nav_ = std::make_unique<LiveNavigator>(*t->database(), t->camera(), o, args_.csv);
      recorder_->setNavigator(nav_.get());
      LiveNavigator* nav = nav_.get();
      // Every head's tracker asks the one loop for its frame's inputs.
      for (std::size_t h = 0; h < trackers_.size(); ++h) {
        const int head = static_cast<int>(h);
        trackers_[h]->setInputsProvider(
            [nav, head](mrpt::Clock::time_point when) { return nav->frameInputs(when, head); });
      }
      replay_config_ = replayConfigPath(out_path_);
      writeReplayConfig(replay_config_, *t, live_keys_);
    }
    int running = 0;
    for (auto& r : runners_) running += r->state() != SensorRunner::State::kFailed;
    for (auto& r : runners_) r->go();
    // The sensors' clocks start now: tests/app/test_live_kill.cpp times its SIGKILL from here.
    std::printf("live: sensors running\n");
    std::fflush(stdout);
    printReports();
    if (args_.gui) {
      std::string why;
      if (!display_.open("startracker live", &why))
        log::warn("--gui: %s; running without a window", why.c_str());
    }
    return running;
  }

  /// Records until a signal, --duration, the window or the sensors end it; returns why.
  std::string runUntilStopped() {
    using clock = std::chrono::steady_clock;
    const auto t_start = clock::now();
    auto last_gui = t_start;
    for (;;) {
      if (stopSignal()) return stopSignalName();
      elapsed_s_ = std::chrono::duration<double>(clock::now() - t_start).count();
      if (args_.duration_s > 0 && elapsed_s_ >= args_.duration_s) return "--duration";
      recorder_->record(queue_.takeAll(0.05));
      printReports();
      if (display_.isOpen() && clock::now() - last_gui > std::chrono::milliseconds(100)) {
        last_gui = clock::now();
        showFrame();
        if (display_.quitRequested()) return "the window (q)";
      }
      int alive = 0;
      for (auto& r : runners_)
        alive += r->state() != SensorRunner::State::kFailed &&
                 r->state() != SensorRunner::State::kFinished;
      if (alive == 0) return "all sensors stopped or finished";
    }
  }

  /// Stops the sensors first, then writes what they had already delivered: nothing received
  /// is lost, and the rawlog is closed properly. The star trackers stop first, while the other
  /// sensors run and their observations keep reaching the navigator: a tracker in the middle
  /// of a frame may be waiting for them (replay's schedule, live_navigator.hpp).
  void stop() {
    stopRunners(true);
    stopRunners(false);
    recorder_->record(queue_.takeAll(0.0));
    recorder_->finish();
    printReports();
    if (nav_) {
      nav_->flush();
      for (CStarTrackerSensor* head : trackers_) head->setInputsProvider({});
    }
    recorder_->writeMarker(*recordingMarker(kRecordingEndLabel, "startracker live: end of recording",
                                            recorder_->lastWritten()));
    writer_->close();
    display_.close();
  }

  void printSummary(const std::string& why_stop) const {
    std::printf("live: stopped by %s after %.1f s\n", why_stop.c_str(), elapsed_s_);
    recorder_->printRawlogSummary(out_path_.string(), stdout);
    std::size_t delivered = 0;
    for (auto& r : runners_) {
      const char* st = r->state() == SensorRunner::State::kFailed     ? "FAILED"
                       : r->state() == SensorRunner::State::kFinished ? "finished"
                                                                       : "ok";
      std::printf("sensor '%s' %s: %zu observations, %s\n", r->section().c_str(),
                  r->driver().c_str(), r->observations(), st);
      delivered += r->observations();
    }
    // Every observation a sensor delivered must be in the rawlog (scripts/soak.sh checks).
    std::printf("observations: %zu delivered, %zu recorded, %zd lost\n", delivered,
                recorder_->written(), static_cast<std::ptrdiff_t>(delivered - recorder_->written()));
    recorder_->printTrackerSummary(stdout);
    // One line per head, named when there are several (issue 39: two unnamed "camera:" lines).
    for (const CStarTrackerSensor* t : trackers_) {
      std::string c = t->cameraReport();
      if (c.empty()) continue;
      if (trackers_.size() > 1 && c.rfind("camera:", 0) == 0)
        c = "camera " + t->getSensorLabel() + ":" + c.substr(7);
      std::printf("%s\n", c.c_str());
    }
    if (!nav_) return;
    const auto s = nav_->stats();
    std::printf("filter: %d fixes (%d accepted, %d rejected, %d ignored while waiting for "
                "lost-in-space), %d re-initialisations, %d warnings\n",
                s.fixes, s.accepted, s.rejected, s.ignored, s.reinits, s.warnings);
    // Frames that asked the loop before everything earlier was in (a sensor later than the
    // reorder window): replay may make other fixes from those.
    std::printf("schedule: %d frame(s) off replay's schedule\n", s.off_schedule);
    if (!replay_config_.empty()) {
      std::printf("replay: startracker replay %s --config %s\n", out_path_.c_str(),
                  replay_config_.c_str());
    }
    for (const auto& w : nav_->warnings()) log::warn("%s", w.c_str());
    nav_->printSummaries(stdout);
    if (const int rows = nav_->finishCsv(); rows >= 0)
      std::printf("csv: %s (%d rows)\n", args_.csv.c_str(), rows);
  }

 private:
  /// Several star trackers are several camera heads of one body: [navigator] head_labels
  /// names the further heads' cameras (image_label); the first head is the tracker whose
  /// camera is not among them, and its database and camera serve the navigator. Orders
  /// trackers_ so, and checks that each further head's fixes carry the label the navigator
  /// reads them under (<first head's sensorLabel>_<camera label>).
  void orderHeads() {
    const std::vector<std::string>& heads = nav_opts_.head_labels;
    const std::string where = args_.config + ": [navigator] head_labels";
    if (trackers_.size() != 1 + heads.size())
      throw InputError(where + " names " + std::to_string(heads.size()) +
                       " further head(s), but the file has " + std::to_string(trackers_.size()) +
                       " CStarTrackerSensor section(s): one per head");
    std::vector<CStarTrackerSensor*> ordered(trackers_.size(), nullptr);
    for (CStarTrackerSensor* t : trackers_) {
      const auto it = std::find(heads.begin(), heads.end(), t->imageLabel());
      const std::size_t h = it == heads.end() ? 0 : 1 + std::size_t(it - heads.begin());
      if (ordered[h])
        throw InputError(where + ": two CStarTrackerSensor sections have image_label = " +
                         t->imageLabel() + " (each head its own camera label)");
      ordered[h] = t;
    }
    trackers_ = ordered;
    for (std::size_t h = 1; h < trackers_.size(); ++h) {
      const std::string want = headFixLabel(trackers_[0]->getSensorLabel(), heads[h - 1]);
      if (trackers_[h]->getSensorLabel() != want)
        throw InputError(where + ": the CStarTrackerSensor of head '" + heads[h - 1] +
                         "' needs sensorLabel = " + want + " (found " +
                         trackers_[h]->getSensorLabel() + ")");
    }
  }

  void stopRunners(bool trackers) {
    std::vector<SensorRunner*> group;
    for (auto& r : runners_) {
      if ((dynamic_cast<CStarTrackerSensor*>(&r->sensor()) != nullptr) == trackers)
        group.push_back(r.get());
    }
    for (auto* r : group) r->requestStop();
    const auto exited = [&] {
      return std::all_of(group.begin(), group.end(), [](auto* r) { return r->exited(); });
    };
    while (!exited()) recorder_->record(queue_.takeAll(0.01));
    for (auto* r : group) r->stop();
  }
  void printReports() {
    for (const auto& m : queue_.takeReports()) log::info("%s", m.c_str());
  }
  void showFrame() {
    if (trackers_.empty()) return;
    Quat q;
    Mat3 P;
    std::optional<Quat> att;
    if (nav_ && nav_->current(q, P)) att = q;
    const auto fix = trackers_.front()->lastObservation();
    display_.show(trackers_.front()->lastImage(), fix.get(), att);
  }

  const LiveArgs& args_;
  fs::path out_path_;
  NavigatorOptions nav_opts_;
  LiveIniKeys live_keys_;
  fs::path replay_config_;
  bool nav_enabled_ = true;
  std::unique_ptr<RawlogWriter> writer_;
  ObservationQueue queue_;
  std::vector<std::unique_ptr<SensorRunner>> runners_;
  std::vector<CStarTrackerSensor*> trackers_;
  std::unique_ptr<LiveNavigator> nav_;
  std::unique_ptr<LiveRecorder> recorder_;
  LiveDisplay display_;
  double elapsed_s_ = 0;
};

int runLive(const LiveArgs& args) {
  registerStarTrackerClasses();
  registerSimulatedSensors();
  std::error_code ec;
  if (!fs::is_regular_file(args.config, ec))
    throw InputError("live config '" + args.config + "': no such file");
  const fs::path config = fs::absolute(args.config);
  const auto cfg_file = openIniFile(config.string());
  mrpt::config::CConfigFile& cfg = *cfg_file;

  // Outputs are relative to where the user runs (rawlog_file as -o), checked before any
  // sensor starts; inputs inside the .ini are relative to its folder.
  LiveArgs checked = args;
  const std::string out =
      args.out.empty() ? readLiveIni(IniReader{cfg, args.config}).global.rawlog_file : args.out;
  const fs::path out_path = fs::absolute(out).lexically_normal();
  if (!args.force) replaceEarlierRun(out_path.string(), false);  // refused before any work
  // The recording and its replay .ini are one run's: replaceEarlierRun decided for both.
  prepareOutputFile(out_path.string(), args.out.empty() ? args.config + ": [global] rawlog_file"
                                                        : std::string("-o"), /*replace=*/true);
  prepareOutputFile(replayConfigPath(out_path).string(), "-o", /*replace=*/true);
  if (!args.csv.empty()) {
    checked.csv = fs::absolute(args.csv).lexically_normal().string();
    refuseSameFile(checked.csv, "--csv",
                   {{out_path.string(), "the recording"},
                    {replayConfigPath(out_path).string(), "the recording's replay .ini"},
                    {args.config, "the live .ini"}});
    prepareOutputFile(checked.csv, "--csv", args.force);
  }
  fs::current_path(config.parent_path());  // the .ini's relative paths

  LiveSession session(checked, cfg, out_path);
  installStopSignals();  // Ctrl-C is live's normal end: exit 0 after the summary
  const int running = session.start();
  const std::string why_stop = running > 0 ? session.runUntilStopped() : "no sensor started";
  session.stop();
  session.printSummary(why_stop);
  std::fflush(stdout);
  if (running > 0) return kExitOk;
  return session.allFailedOnInput() ? kExitUsage : kExitFailure;
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
  cmd->add_option("-o,--output", args->out,
                  "Output rawlog (default [global] rawlog_file, in the current directory); "
                  "<stem>_tracker.ini beside it replays it to the same fixes");
  cmd->add_option("--duration", args->duration_s, "Stop after this many seconds (0 = until "
                                                  "Ctrl-C / SIGTERM)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--csv", args->csv, "Trajectory CSV of the filter, one row per frame (as "
                                      "replay's)");
  cli::addForceFlag(*cmd, args->force,
                "Replace existing outputs: the recording at -o (and empty its images folder), "
                "--csv (without it an existing output is refused)");
  cmd->add_flag("--gui", args->gui, "Show the frame, blobs, identified stars and attitude");
  cmd->callback([args, &run] { run = [args] { return runLive(*args); }; });
}

}  // namespace st::app
