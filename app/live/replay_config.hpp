/// @file replay_config.hpp
/// The tracker.ini with which `replay` re-runs a live recording the way the live run ran:
/// the star tracker sensor's effective options (the simulated source's exposure and noise
/// filled in), its star database recipe (the epoch it used, exactly) and camera, and the
/// live .ini's [filter] and [navigator]. Live and replay then make the same fixes from the
/// same frames: LiveNavigator asks the loop on replay's schedule. Written beside the rawlog
/// as `<stem>_tracker.ini`, which `startracker replay RAWLOG` picks up on its own.
#pragma once
#include <filesystem>
#include <string>

#include "navigation/tracker_ini.hpp"
#include "sensors/mrpt/star_tracker_sensor.hpp"

namespace st::app {

/// `<folder>/<stem>_tracker.ini` for a rawlog path.
std::filesystem::path replayConfigPath(const std::filesystem::path& rawlog);

/// The file's text. Relative database/catalog paths of the sensor (relative to the working
/// directory of the live run) are written absolute.
std::string replayConfigText(const CStarTrackerSensor& tracker, const LiveIniKeys& live);

/// Writes it; throws InputError naming the file when it cannot be written.
void writeReplayConfig(const std::filesystem::path& path, const CStarTrackerSensor& tracker,
                       const LiveIniKeys& live);

}  // namespace st::app
