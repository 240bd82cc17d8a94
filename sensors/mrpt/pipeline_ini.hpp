/// @file pipeline_ini.hpp
/// The .ini keys of a star tracker (TrackerOptions, plus the observation label), read the
/// same way by CStarTrackerSensor (in its own section) and by the navigator (in [pipeline]):
/// one list of keys, one meaning for each.
#pragma once
#include <set>
#include <string>

#include "config/ini_reader.hpp"
#include "sensors/mrpt/observation_from_frame.hpp"
#include "sensors/tracking/tracker_options.hpp"

namespace st {

/// The keys readPipelineOptions understands (for IniReader::onlyKeys).
const std::set<std::string>& pipelineIniKeys();

/// Reads the tracker keys of `section` that are present over `o` (absent keys keep o's
/// values), then checks the result (TrackerOptions::isValid). `solver` names the Wahba solver
/// of tracking and of lost-in-space; `identify_solver` overrides the latter. Throws
/// InputError naming the file, section and key.
void readTrackerOptions(const IniReader& r, const std::string& section, TrackerOptions& o);

/// readTrackerOptions into o.tracker, and `sensor_label`.
void readPipelineOptions(const IniReader& r, const std::string& section, PipelineOptions& o);

}  // namespace st
