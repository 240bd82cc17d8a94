// `startracker replay RAWLOG`: the navigator (pipeline + MEKF) over a recorded rawlog, with a
// summary, the trajectory CSV, an output rawlog with STAR_TRACKER observations and plots.
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/system/datetime.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>

#include "app/cli/common_flags.hpp"
#include "app/command.hpp"
#include "app/earlier_run.hpp"
#include "app/live/step_report.hpp"
#include "app/live/replay_config.hpp"
#include "common/output_file.hpp"
#include "app/plot.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "common/log.hpp"
#include "common/mrpt_convert.hpp"
#include "common/progress.hpp"
#include "common/stop_signal.hpp"
#include "fusion/consistency.hpp"
#include "navigation/nav_step.hpp"
#include "navigation/navigator.hpp"
#include "navigation/run_summary.hpp"
#include "navigation/tracker_config.hpp"
#include "sensors/mrpt/rawlog_io.hpp"
#include "sensors/mrpt/camera_ini.hpp"

namespace st::app {

namespace {

namespace fs = std::filesystem;

struct ReplayOpts {
  std::string rawlog, config, output, csv, plots;
  bool realtime = false;
  bool force = false;  ///< replace existing outputs (-o with its images link, --csv)
  bool strict = false;  ///< a damaged rawlog is an error instead of replayed up to the damage
};

/// External images of the output rawlog: `<out stem>_Images` points to the input's folder.
void linkImages(const std::string& input, const std::string& output) {
  const fs::path in_dir = fs::absolute(rawlogImagesDir(input));
  const fs::path out_dir = fs::absolute(rawlogImagesDir(output));
  if (!fs::is_directory(in_dir)) return;  // inline images
  std::error_code ec;
  if (fs::equivalent(in_dir, out_dir, ec)) return;
  if (fs::is_symlink(out_dir)) fs::remove(out_dir, ec);
  if (fs::exists(out_dir)) {
    log::warn("%s exists; external images are read from there", out_dir.c_str());
    return;
  }
  fs::create_directory_symlink(in_dir, out_dir, ec);
  if (ec) {
    throw InputError(out_dir.string() + ": cannot link the input images (" + ec.message() + ")");
  }
}

/// Plots of a run; without a filter (no gyro) the raw fixes take the filter's place and there is
/// no bias plot. Returns the names drawn.
std::string plots(const std::vector<NavStep>& steps, const std::string& dir) {
  const bool filtered =
      std::any_of(steps.begin(), steps.end(), [](const NavStep& s) { return s.initialized; });
  const auto scored = [filtered](const NavStep& s) {
    return s.has_truth && (filtered ? s.initialized : s.fix);
  };
  Plot err = makePlot(filtered ? "Attitude error (filter - truth) with +-3 sigma"
                               : "Attitude error (raw fixes, no filter - truth) with +-3 sigma",
                      "time [s]", "error [arcsec]");
  const char* axes[3] = {"x", "y", "z (roll)"};
  const char* colors[3] = {"#1f77b4", "#2ca02c", "#d62728"};
  for (int i = 0; i < 3; ++i) {
    PlotSeries e(std::string("error ") + axes[i], PlotStyle::Lines), s3("", PlotStyle::Lines),
        s3n("", PlotStyle::Lines);
    e.color = s3.color = s3n.color = colors[i];
    s3.dashed = s3n.dashed = true;
    s3.title = std::string("+-3 sigma ") + axes[i];
    for (const NavStep& s : steps) {
      if (!scored(s)) continue;
      const double ei = filtered ? s.error.rotvec_body[i] : s.fix_error.rotvec_body[i];
      const double si = filtered ? s.sigma_att[i] : std::sqrt(std::max(0.0, s.cov_fix(i, i)));
      e.x.push_back(s.t);
      e.y.push_back(rad2arcsec(ei));
      s3.x.push_back(s.t);
      s3.y.push_back(3 * rad2arcsec(si));
      s3n.x.push_back(s.t);
      s3n.y.push_back(-3 * rad2arcsec(si));
    }
    err.series.push_back(e);
    err.series.push_back(s3);
    err.series.push_back(s3n);
  }
  Plot nees = makePlot(filtered ? "Attitude NEES (3 dof) with the 95 % chi-square band"
                                : "Raw fix NEES (3 dof, no filter) with the 95 % chi-square band",
                       "time [s]", "NEES");
  PlotSeries n("NEES", PlotStyle::Points);
  for (const NavStep& s : steps) {
    if (!scored(s)) continue;
    n.x.push_back(s.t);
    n.y.push_back(filtered ? s.nees : s.fix_nees);
  }
  nees.series.push_back(n);
  nees.ref_lines = {{chiSquareQuantile(0.025, 3), "chi2(3) 2.5 %"},
                    {chiSquareQuantile(0.975, 3), "chi2(3) 97.5 %"}};
  nees.log_y = true;
  Plot bias = makePlot("Gyro bias estimate", "time [s]", "bias [deg/h]");
  for (int i = 0; i < 3; ++i) {
    PlotSeries b(std::string("bias ") + "xyz"[i], PlotStyle::Lines);
    for (const NavStep& s : steps) {
      if (!s.initialized) continue;
      b.x.push_back(s.t);
      b.y.push_back(s.bias[i] * kDegPerRad * 3600.0);
    }
    bias.series.push_back(b);
  }
  Plot stars = makePlot("Stars matched per frame", "time [s]", "stars");
  Plot ftime = makePlot("Time per frame", "time [s]", "time [ms]");
  PlotSeries ns("stars", PlotStyle::Steps), ft("pipeline", PlotStyle::Points);
  for (const NavStep& s : steps) {
    if (!s.has_frame) continue;
    ns.x.push_back(s.t);
    ns.y.push_back(s.stars_matched);
    ft.x.push_back(s.t);
    ft.y.push_back(s.frame_time_s * 1e3);
  }
  stars.series.push_back(ns);
  ftime.series.push_back(ft);
  std::vector<std::pair<const Plot*, const char*>> all = {{&err, "error"}, {&nees, "nees"}};
  if (filtered) all.push_back({&bias, "bias"});
  all.push_back({&stars, "stars"});
  all.push_back({&ftime, "frame_time"});
  std::string names;
  for (const auto& [p, name] : all) {
    const std::string png = (fs::path(dir) / (std::string(name) + ".png")).string();
    try {
      savePlot(*p, png);
    } catch (const ProcessingError& e) {
      log::warn("plot %s not drawn: %s", png.c_str(), e.what());
      break;
    }
    names += (names.empty() ? "" : ",") + std::string(name);
  }
  return names;
}

/// Every output path is checked before the (possibly long) run, so a typo fails at once.
void prepareOutputs(const ReplayOpts& o) {
  // Two outputs on one file first: that names the slip better than "it exists".
  refuseSameFile(o.csv, "--csv", {{o.rawlog, "the input rawlog"}, {o.output, "-o/--output"}});
  if (!o.output.empty()) {
    std::error_code ec;
    if (fs::equivalent(o.output, o.rawlog, ec))
      throw InputError("-o/--output " + o.output +
                       ": the output rawlog must differ from the input");
    replaceEarlierRun(o.output, o.force);  // refused without -f, with its images folder
    prepareOutputFile(o.output, "-o/--output", /*replace=*/true);
  }
  if (!o.csv.empty()) prepareOutputFile(o.csv, "--csv", o.force);
  if (!o.plots.empty()) prepareOutputDir(o.plots, "--plots");
}

/// MRPT reads external images from `<stem>_Images` beside the rawlog; a missing folder would
/// otherwise show as one loader error per frame and no frame processed.
void checkImages(const ExternalImages& im, const ReplayOpts& o, const std::string& camera_label) {
  if (im.missing == 0) return;
  const std::string dir = fs::absolute(rawlogImagesDir(o.rawlog)).string();
  const std::string where = "external images are read from " + dir +
                            " (MRPT's <stem>_Images beside the rawlog)";
  if (im.missing == im.external) {
    throw InputError(o.rawlog + ": none of its " + std::to_string(im.external) + " " +
                     camera_label + " images found: " + where + "; first missing: " +
                     im.first_missing);
  }
  log::warn(
      "%zu of %zu %s images missing (first: %s); %s; those frames "
      "are skipped",
      im.missing, im.external, camera_label.c_str(), im.first_missing.c_str(), where.c_str());
}

/// A live run's <stem>_tracker.ini beside the rawlog (app/live/replay_config.hpp), so that a
/// plain `replay X.rawlog` makes the live run's fixes; "" when there is none.
std::string recordedTrackerConfig(const std::string& rawlog) {
  const fs::path ini = replayConfigPath(rawlog);
  std::error_code ec;
  return fs::is_regular_file(ini, ec) ? ini.string() : std::string();
}

int runReplay(const ReplayOpts& o) {
  // Ctrl-C / SIGTERM stop between observations: what was replayed is flushed and summed up.
  // Caught from the start, so that one during the scan or the database build stops the run
  // before its first observation (a second one kills).
  installStopSignals();
  if (!fs::is_regular_file(o.rawlog)) throw InputError(o.rawlog + ": rawlog not found");
  TrackerConfig cfg;
  if (!o.config.empty()) {
    cfg = TrackerConfig::load(o.config);
  } else if (const std::string recorded = recordedTrackerConfig(o.rawlog); !recorded.empty()) {
    log::info("using %s, the tracker and filter of the live run that recorded this rawlog "
              "(--config to choose another)",
              recorded.c_str());
    cfg = TrackerConfig::load(recorded);
  }
  prepareOutputs(o);

  // Two passes, nothing held: a scan (what the run needs to know before its first step), then
  // the replay itself, each streaming the file (an hour at 10 Hz is 468,000 observations: held,
  // 1.7 GB). External images stay on disk until a frame needs them. A rawlog cut or damaged
  // part way (a recording interrupted by a crash or power loss) replays the intact
  // observations before the damage, as MRPT's own tools read it, and says once where it
  // stopped; --strict makes that an error. A file with no readable object stays one.
  RawlogDamage damage;
  std::optional<CameraModel> camera = cfg.camera;
  std::optional<mrpt::Clock::time_point> t_first, t_last;
  bool has_gyro = false, recording_start = false, recording_end = false;
  ExternalImages images;
  const std::size_t n_obs = visitRawlogUpToDamage(
      o.rawlog,
      [&](const mrpt::obs::CObservation::Ptr& ob) {
        const bool marker = isRecordingMarker(*ob, kRecordingStartLabel) ||
                            isRecordingMarker(*ob, kRecordingEndLabel);
        if (!t_first && !marker) t_first = ob->timestamp;
        if (!marker) t_last = ob->timestamp;
        recording_start = recording_start || isRecordingMarker(*ob, kRecordingStartLabel);
        recording_end = recording_end || isRecordingMarker(*ob, kRecordingEndLabel);
        has_gyro = has_gyro || isGyroObservation(*ob, cfg.nav);
        images.add(*ob, cfg.nav.camera_label);
        if (camera || ob->sensorLabel != cfg.nav.camera_label) return;
        if (auto img = std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(ob))
          camera = cameraFromTCamera(img->cameraParams);
      },
      &damage);
  if (damage.damaged) {
    if (o.strict) throw InputError(damage.message + " (--strict)");
    // How much is kept, in objects and seconds: what came after the damage is lost.
    log::warn("%s; replaying them (%zu observations, %.1f s of recording; what followed is "
              "lost; --strict makes this an error)",
              damage.message.c_str(), damage.object,
              t_first && t_last ? mrpt::system::timeDifference(*t_first, *t_last) : 0.0);
  }
  if (n_obs == 0) throw InputError(o.rawlog + ": no observations");
  if (recording_start && !recording_end && !damage.damaged)
    log::warn("%s: the recording was cut: it has no %s marker (the live run that wrote it was "
              "killed or lost power); replaying its %zu observations (%.1f s)",
              o.rawlog.c_str(), kRecordingEndLabel, n_obs,
              t_first && t_last ? mrpt::system::timeDifference(*t_first, *t_last) : 0.0);
  if (!camera) {
    throw InputError(o.rawlog + ": no " + cfg.nav.camera_label +
                     " (CObservationImage) observation: nothing to replay");
  }
  checkImages(images, o, cfg.nav.camera_label);
  // Without a gyro nothing carries the attitude from one frame to the next: a filter fed fixes
  // alone lags a moving body until its gate refuses every fix (issue 21: 1.7 deg off on the
  // tour's slew). Unless the ini asks for the gyroless filter, each frame is solved on its own.
  if (!has_gyro && cfg.nav.fusion.filter.model == MekfOptions::Model::kGyroless) {
    log::info("no %s observations: gyroless filter ([filter] model = gyroless): the body rate "
              "is estimated from the fixes",
              cfg.nav.gyro_label.c_str());
  } else if (!has_gyro) {
    log::warn(
        "no %s observations: without gyro rates there is no attitude "
        "filter; every frame is solved lost-in-space and the raw fixes are the output "
        "(the CSV's filter columns are nan, no filter NEES; [filter] model = gyroless "
        "estimates the rate from the fixes)",
        cfg.nav.gyro_label.c_str());
    cfg.nav.fusion.filter_enabled = false;
  }
  const double epoch = julianYear(*t_first);
  const auto t_db = std::chrono::steady_clock::now();
  const std::shared_ptr<const StarDatabase> db_held = makeDatabase(cfg.database, *camera, epoch);
  const StarDatabase& db = *db_held;
  const double db_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_db).count();

  // The output rawlog is written under a temporary name and renamed when complete.
  std::unique_ptr<PendingOutput> out_file;
  std::unique_ptr<RawlogWriter> writer;
  if (!o.output.empty()) {
    out_file = std::make_unique<PendingOutput>(o.output);
    writer = std::make_unique<RawlogWriter>(out_file->tempPath());
    linkImages(o.rawlog, o.output);
  }
  std::size_t star_tracker_written = 0, star_tracker_replaced = 0;
  Navigator nav(db, *camera, cfg.nav);
  // Steps are reported as they finish and kept only for plots (live's StepReport).
  StepReport report(o.csv, !o.plots.empty());
  nav.setKeepSteps(false);
  nav.setStepCallback([&](const NavStep& s, const std::vector<CObservationStarTracker::Ptr>& fixes) {
    for (const auto& st : fixes) {
      if (!writer) break;
      writer->write(*st);
      ++star_tracker_written;
    }
    // -v: every frame's outcome as it happens (issue 39: -v added nothing outside montecarlo).
    if (s.has_frame)
      log::debug("t = %.3f s: %s, %d stars matched%s%s%s", s.t, toString(s.mode), s.stars_matched,
                 s.failure != FrameFailure::kNone ? ", failed: " : "",
                 s.failure != FrameFailure::kNone ? toString(s.failure) : "",
                 s.reason.empty() ? "" : ("; " + s.reason).c_str());
    report.push(s);
  });

  ProgressBar bar("replay", n_obs, true);  // silent under -q (common/progress)
  const auto wall0 = std::chrono::steady_clock::now();
  std::size_t n_done = 0;
  // The scan's observations again: exactly those (the damage, if any, comes after them).
  RawlogReader reader(o.rawlog);
  for (std::size_t i = 0; i < n_obs && !stopSignal(); ++i, n_done = i) {
    const mrpt::obs::CObservation::Ptr ob = reader.next();
    if (!ob) throw InputError(o.rawlog + ": changed while replayed (object " + std::to_string(i) +
                              " is gone)");
    // (A recording's start/end markers are stamped by the wall clock, not the sensors'.)
    if (o.realtime && !isRecordingMarker(*ob, kRecordingStartLabel) &&
        !isRecordingMarker(*ob, kRecordingEndLabel)) {
      const double dt = mrpt::system::timeDifference(*t_first, ob->timestamp);
      std::this_thread::sleep_until(wall0 + std::chrono::duration_cast<std::chrono::nanoseconds>(
                                                std::chrono::duration<double>(std::max(0.0, dt))));
    }
    // A recording's own fixes (a live run's STAR_TRACKER) are replaced by this run's, not
    // written beside them under one label and time.
    const bool replaced = writer && nav.isFixLabel(ob->sensorLabel) &&
                          dynamic_cast<const CObservationStarTracker*>(ob.get());
    star_tracker_replaced += replaced;
    if (writer && !replaced) writer->write(*ob);
    nav.push(ob);
    bar.update(i + 1);
  }
  const bool interrupted = n_done < n_obs;
  nav.flush();
  report.flush();
  bar.finish();
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  if (writer) {
    writer->close();
    out_file->commit();
  }

  for (const auto& w : nav.warnings()) log::warn("%s", w.c_str());
  if (nav.warningCount() > int(nav.warnings().size()))
    log::info("... %d warnings in all", nav.warningCount());

  // ---- summary ----
  const std::string upto =
      damage.damaged ? " (up to the damage at object " + std::to_string(damage.object) + ")" : "";
  if (interrupted)
    std::printf("replay: interrupted by %s after %zu of %zu observations: the summary and "
                "the outputs are of those\n",
                stopSignalName(), n_done, n_obs);
  std::printf("%s: %zu observations%s, camera %s\n", o.rawlog.c_str(), n_obs, upto.c_str(),
              camera->describe().c_str());
  std::printf("database: %zu stars (%s, %.1f s)\n", db.stars().size(),
              cfg.database.path.empty() ? "built in memory" : cfg.database.path.c_str(), db_s);
  const StepReport::Counts& c = report.counts();
  const double pct = c.frames ? 100.0 / c.frames : 0.0;
  std::printf("frames: %d, solved %.1f %%, lost-in-space %d (%d re-acquired in the frame), "
              "tracking %.1f %%, rejected by the filter %d, re-initialisations %d\n",
              c.frames, c.solved * pct, c.lost_in_space, c.reacquired, c.tracking * pct,
              c.rejected, nav.reinitializations());
  std::printf("time per frame: %.3f ms (pipeline), replay %.1f frames/s wall\n",
              c.frames ? 1e3 * c.frame_time_s / c.frames : 0.0, c.frames / std::max(wall_s, 1e-9));
  report.print(stdout);

  if (!o.csv.empty()) {
    const int rows = report.finishCsv();
    std::printf("csv: %s (%d rows)\n", o.csv.c_str(), rows);
  }
  if (writer) {
    std::printf("rawlog: %s (%zu observations, %zu STAR_TRACKER%s)\n", o.output.c_str(),
                writer->count(), star_tracker_written,
                star_tracker_replaced
                    ? (", in place of the recording's " + std::to_string(star_tracker_replaced))
                          .c_str()
                    : "");
  }
  if (!o.plots.empty()) {
    const std::string drawn = plots(report.steps(), o.plots);
    std::printf("plots: %s/{%s}.png\n", o.plots.c_str(), drawn.c_str());
  }
  if (interrupted) return kExitInterrupted;
  return c.solved > 0 ? kExitOk : kExitFailure;
}

}  // namespace

void addReplayCommand(CLI::App& root, CommandRun& run) {
  auto* cmd = root.add_subcommand(
      "replay",
      "Run the star tracker + attitude filter over a rawlog (CAMERA, GYRO, optional "
      "GROUND_TRUTH): summary, trajectory CSV, output rawlog with STAR_TRACKER, plots");
  auto o = std::make_shared<ReplayOpts>();
  cmd->add_option("rawlog", o->rawlog, "Input rawlog")->required();
  cmd->add_option("--config", o->config,
                  "tracker.ini: [pipeline] [filter] [navigator] [database] [camera] (see "
                  "docs/configuration.md; default: <stem>_tracker.ini beside the rawlog if a "
                  "live run wrote one, else the built-in defaults)");
  cmd->add_option("-o,--output", o->output, "Output rawlog: the input + STAR_TRACKER");
  cmd->add_option("--csv", o->csv, "Trajectory CSV, one row per frame");
  cmd->add_option("--plots", o->plots, "Folder for PNG plots (gnuplot)");
  cli::addForceFlag(*cmd, o->force,
                "Replace existing outputs: -o (and its images link), --csv (without it an "
                "existing output is refused; plots in --plots are replaced)");
  cmd->add_flag("--realtime", o->realtime, "Replay at the recorded speed");
  cmd->add_flag("--strict", o->strict,
                "A rawlog truncated or damaged part way is an error (exit 2); by default the "
                "observations before the damage are replayed with a warning");
  cmd->callback([o, &run] { run = [o] { return runReplay(*o); }; });
}

}  // namespace st::app
