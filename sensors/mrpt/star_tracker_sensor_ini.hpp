/// @file star_tracker_sensor_ini.hpp
/// The .ini section of CStarTrackerSensor as one SectionSchema: its own keys, MRPT's common
/// sensor keys, the simulated camera's keys it passes on (image_source = simulated) and every
/// tracker key (pipeline_ini.hpp). Strict, except that with image_source = camera and the
/// camera's keys in this same section (camera_section empty or this section) the keys of
/// MRPT's CCameraSensor are that driver's to check: then only our keys are read (old key
/// names are still refused).
#pragma once
#include <string>

#include "config/schema.hpp"
#include "sensors/tracking/tracker_options.hpp"

namespace mrpt::config {
class CConfigFileBase;
}

namespace st {

struct StarTrackerSensorKeys {
  // MRPT's CGenericSensor keys
  std::string driver = "CStarTrackerSensor";
  double process_rate = 0;
  int max_queue_len = 200, grab_decimation = 1;
  std::string sensorLabel = "STAR_TRACKER";
  // the image source
  std::string image_source;  ///< simulated | camera
  std::string image_label = "CAMERA";
  bool emit_image = true;
  std::string camera_file, camera_file_section = "camera";
  std::string camera_section;  ///< empty: this section
  /// camera: a recording's clock instead of the grabber's (frame k at start + k / rate)
  double frame_rate_hz = 0;
  std::string frame_start_time;  ///< UTC of frame 0; empty = the first frame's grabber stamp
  // simulated: CSimulatedStarCamera's keys, read by it from this section
  std::string scenario_file, seed, truth_label = "GROUND_TRUTH";
  int scenario_head = 0;
  Vec3 mount_ypr_deg = Vec3::Zero();
  // the star database
  std::string database_file, catalog_file;
  double mag_limit = 6.5;
  double epoch_jyear = 0;  ///< 0: the scenario's epoch, else the clock's
  bool aberration = true;
  TrackerOptions tracker;
};

const SectionSchema<StarTrackerSensorKeys>& starTrackerSensorSchema();

/// Reads the section (see the file comment), then checks the tracker options once.
StarTrackerSensorKeys readStarTrackerSensorKeys(const IniReader& r, const std::string& section);

/// Whether `section` configures a CStarTrackerSensor (its driver names it).
bool isStarTrackerSensorSection(const mrpt::config::CConfigFileBase& cfg,
                                const std::string& section);
/// Strict read, then the effective section in ini form (`startracker config`).
std::string printStarTrackerSensorSection(const IniReader& r, const std::string& section);

}  // namespace st
