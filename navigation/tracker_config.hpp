/// @file tracker_config.hpp
/// tracker.ini, the configuration of `replay` (and the navigator of `live`), and the star
/// database it names.
#pragma once
#include <optional>
#include <set>
#include <string>

#include "catalog/star_database.hpp"
#include "config/ini_reader.hpp"
#include "navigation/navigator.hpp"
#include "sensors/camera/camera_model.hpp"

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

/// tracker.ini, every section optional:
///   [filter]    arw_deg_rt_h, rrw_deg_h_rt_h, bias_sigma_deg_h (gyro datasheet numbers),
///               gate_probability, gate (true/false), update = attitude | stars
///   [navigator] reinit_after_rejections, reorder_window_s, gyro_gap_factor, rate_window_s,
///               camera_label, gyro_label, truth_label
///   [pipeline]  the keys of sensors/mrpt/pipeline_ini.hpp (PipelineOptions, same names),
///               as in a CStarTrackerSensor section
///   [database]  path, catalog, mag_limit, epoch_jyear, aberration
///   [camera]    CameraModel::loadIni keys; present = overrides the rawlog's camera
/// Unknown keys in these sections are errors (a typo must not silently keep a default).
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

/// Reads the [filter] and [navigator] sections (the fusion loop's options and the rawlog
/// labels) shared by tracker.ini and the live app's .ini; `extra_navigator_keys` are allowed
/// in [navigator] for the caller to read (e.g. the live app's `enabled`).
void readFusionSections(const IniReader& r, NavigatorOptions& n,
                        const std::set<std::string>& extra_navigator_keys);

/// The live app's [filter] / [navigator] (tracker.ini's reader, plus `enabled`; the reorder
/// window defaults to 0.5 s there: a fix arrives after its processing time).
NavigatorOptions liveNavigatorOptions(const mrpt::config::CConfigFileBase& cfg,
                                      const std::string& source, bool* enabled);

/// Builds (or loads) the database of `src` for a camera; `data_epoch_jyear` is used when the
/// source gives none. Throws InputError naming the file for a bad database/catalog.
StarDatabase makeDatabase(const DatabaseSource& src, const CameraModel& camera,
                          double data_epoch_jyear);

}  // namespace st
