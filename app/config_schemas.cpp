// The schemas `startracker config` recognises: one call each. A schema is tried in this
// order; the first to claim a section prints it (a scenario's [camera] is the scenario's).
#include "app/config_schemas.hpp"

#include <mrpt/config/CConfigFileBase.h>

#include <algorithm>

#include "app/montecarlo/run_file.hpp"
#include "navigation/tracker_config.hpp"
#include "sensors/mrpt/star_tracker_sensor_ini.hpp"
#include "sensors/camera/camera_model.hpp"
#include "sensors/sim/scenario.hpp"
#include "sensors/sim/simulated_sensors.hpp"
#include "sensors/mrpt/camera_ini.hpp"

namespace st::app {

namespace {

std::vector<std::string> sectionsWhere(const IniReader& r, const std::string& wanted,
                                       const std::function<bool(const std::string&)>& owns) {
  std::vector<std::string> all, out;
  r.cfg.getAllSections(all);
  for (const auto& s : all)
    if ((wanted.empty() || s == wanted) && owns(s)) out.push_back(s);
  return out;
}

/// A scenario owns [scenario] and the sections it names (present ones).
std::vector<std::string> scenarioSections(const IniReader& r, const std::string&) {
  if (!r.cfg.sectionExists("scenario")) return {};
  std::vector<std::string> out = {"scenario"};
  for (const std::string& sec : scenarioSectionNames(r))
    if (sec != "scenario" && r.cfg.sectionExists(sec)) out.push_back(sec);
  return out;
}

/// The sections of `candidates` present in the file.
std::vector<std::string> presentOf(const IniReader& r, const std::string& wanted,
                                   const std::vector<std::string>& candidates) {
  return sectionsWhere(r, wanted, [&](const std::string& s) {
    return std::find(candidates.begin(), candidates.end(), s) != candidates.end();
  });
}

std::string printCamera(const IniReader& r, const std::string& sec) {
  CameraIniKeys keys = cameraIniKeys(loadCameraIni(r, sec));
  keys.focal_length = r.num(sec, "focal_length", 0.0);  // informational: kept as written
  return cameraIniSchema().print(sec, keys);
}

}  // namespace

void addConfigSchemas(SchemaPrinters& printers) {
  printers.add("scenario", &scenarioSections, [](const IniReader& r, const std::vector<std::string>&) {
    return printScenarioIni(readScenarioIni(r));  // the whole file: its sections name each other
  });
  printers.add("montecarlo run file", sectionNamed(mc::kRunSection), perSection(&mc::printRunFile));
  printers.add(
      "simulated sensor",
      [](const IniReader& r, const std::string& wanted) {
        return sectionsWhere(r, wanted, [&](const std::string& s) { return isSimulatedSensorSection(r.cfg, s); });
      },
      perSection(&printSimulatedSensorSection));
  printers.add(
      "star tracker sensor",
      [](const IniReader& r, const std::string& wanted) {
        return sectionsWhere(r, wanted, [&](const std::string& s) { return isStarTrackerSensorSection(r.cfg, s); });
      },
      perSection(&printStarTrackerSensorSection));
  // A live .ini's own sections; its scenario sections went to the scenario above.
  printers.add(
      "live",
      [](const IniReader& r, const std::string& wanted) {
        return isLiveIni(r) ? presentOf(r, wanted, {"global", "filter", "navigator"})
                            : std::vector<std::string>{};
      },
      [](const IniReader& r, const std::vector<std::string>&) { return printLiveIni(readLiveIni(r)); });
  printers.add(
      "tracker",
      [](const IniReader& r, const std::string& wanted) {
        return isTrackerIni(r) && !isLiveIni(r) ? presentOf(r, wanted, {trackerIniSections().begin(), trackerIniSections().end()})
                               : std::vector<std::string>{};
      },
      [](const IniReader& r, const std::vector<std::string>&) { return printTrackerIni(readTrackerIni(r)); });
  printers.add(
      "camera",
      [](const IniReader& r, const std::string& wanted) {
        return sectionsWhere(r, wanted, [&](const std::string& s) { return r.exists(s, "resolution"); });
      },
      perSection(&printCamera));
}

}  // namespace st::app
