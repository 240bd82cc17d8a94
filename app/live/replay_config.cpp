#include "common/output_file.hpp"
#include "app/live/replay_config.hpp"

#include <fstream>

#include "common/errors.hpp"
#include "navigation/tracker_config.hpp"
#include "sensors/mrpt/camera_ini.hpp"

namespace st::app {

namespace fs = std::filesystem;

fs::path replayConfigPath(const fs::path& rawlog) {
  return rawlog.parent_path() / (rawlog.stem().string() + "_tracker.ini");
}

std::string replayConfigText(const CStarTrackerSensor& tracker, const LiveIniKeys& live) {
  const auto absolute = [](const std::string& p) {
    return p.empty() ? p : fs::absolute(p).lexically_normal().string();
  };
  TrackerIniKeys k;
  k.nav = live.navigator.nav;
  // Replay runs the tracker itself on the recorded frames, found under the tracker's label.
  k.nav.camera_label = tracker.imageLabel();
  k.nav.pipeline = tracker.pipelineOptions();
  const CStarTrackerSensor::DatabaseBuild& b = tracker.databaseBuild();
  k.database.path = absolute(b.file);
  k.database.catalog = absolute(b.catalog);
  k.database.mag_limit = b.mag_limit;
  k.database.epoch_jyear = b.epoch_jyear;
  k.database.aberration = b.aberration;
  k.camera = cameraIniKeys(tracker.camera());
  return "# Written by `startracker live` beside its rawlog: the star tracker and filter of that\n"
         "# run, for `startracker replay RAWLOG --config THIS_FILE` (the same fixes).\n\n" +
         printTrackerIni(k);
}

void writeReplayConfig(const fs::path& path, const CStarTrackerSensor& tracker,
                       const LiveIniKeys& live) {
  writeFileAtomically(path.string(), replayConfigText(tracker, live));
}

}  // namespace st::app
