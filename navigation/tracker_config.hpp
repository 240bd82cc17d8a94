/// @file tracker_config.hpp
/// tracker.ini, the configuration of `replay` (and the navigator of `live`), and the star
/// database it names.
#pragma once
#include <optional>
#include <string>

#include "catalog/star_database.hpp"
#include "config/ini_reader.hpp"
#include "navigation/navigator.hpp"
#include "navigation/tracker_ini.hpp"
#include "sensors/camera/camera_model.hpp"
#include "sensors/mrpt/camera_ini.hpp"

namespace mrpt::config {
class CConfigFileBase;
}

namespace st {

/// Where the star database comes from (tracker.ini [database]).
struct DatabaseSource {
  std::string path;               ///< a saved database (StarDatabase::save); empty = build
  std::string catalog;            ///< catalog for the in-memory build; empty = default
  double mag_limit = 6.5;         ///< in-memory build
  double epoch_jyear = 0;         ///< 0 = the epoch of the data (first timestamp)
  bool aberration = true;
};

/// tracker.ini, every section optional, each read strictly by its schema (unknown keys and old
/// key names are errors naming the file, section and key; `startracker config` prints it):
///   [filter], [navigator]  navigation/tracker_ini.hpp (MekfOptions, FusionOptions, labels)
///   [pipeline]  the tracker keys of sensors/mrpt/pipeline_ini.hpp (PipelineOptions), as in a
///               CStarTrackerSensor section
///   [database]  path, catalog, mag_limit, epoch_jyear, aberration (DatabaseSource)
///   [camera]    CameraModel::loadIni keys; present = overrides the rawlog's camera
/// Relative paths are relative to the .ini's folder.
struct TrackerConfig {
  NavigatorOptions nav;
  DatabaseSource database;
  std::optional<CameraModel> camera;
  std::string source;  ///< file name for messages

  /// Throws InputError naming the file, section and key.
  static TrackerConfig load(const std::string& path);
  static TrackerConfig fromConfig(const mrpt::config::CConfigFileBase& cfg,
                                  const std::string& source, const std::string& base_dir = ".");
};

/// The live app's [filter] / [navigator] (tracker.ini's schemas, plus `enabled`; the reorder
/// window defaults to 0.5 s there: a fix arrives after its processing time). Also checks the
/// live app's [global] (readLiveIni).
NavigatorOptions liveNavigatorOptions(const mrpt::config::CConfigFileBase& cfg,
                                      const std::string& source, bool* enabled);

/// tracker.ini's sections as written (paths unresolved), read strictly and checked.
struct TrackerIniKeys {
  NavigatorOptions nav;  ///< [filter], [navigator] and [pipeline], bound directly
  DatabaseSource database;
  std::optional<CameraIniKeys> camera;
};
TrackerIniKeys readTrackerIni(const IniReader& r);
/// The effective configuration in ini form (reads back to the same).
std::string printTrackerIni(const TrackerIniKeys& k);
/// Whether the file looks like a tracker.ini: it has one of its sections besides [camera].
bool isTrackerIni(const IniReader& r);

/// Builds (or loads) the database of `src` for a camera; `data_epoch_jyear` is used when the
/// source gives none. Throws InputError naming the file for a bad database/catalog.
std::shared_ptr<const StarDatabase> makeDatabase(const DatabaseSource& src, const CameraModel& camera,
                          double data_epoch_jyear);

}  // namespace st
