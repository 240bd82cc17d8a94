#include "sensors/mrpt/star_tracker_sensor_ini.hpp"

#include <mrpt/config/CConfigFileBase.h>

#include "sensors/mrpt/pipeline_ini.hpp"

namespace st {

const SectionSchema<StarTrackerSensorKeys>& starTrackerSensorSchema() {
  using K = StarTrackerSensorKeys;
  static const auto s =
      SectionSchema<K>()
          .choice("driver", &K::driver, {"CStarTrackerSensor"}, "sensor class")
          .add("process_rate", &K::process_rate, "[Hz] doProcess rate; at least the frame rate")
          .required()
          .add("max_queue_len", &K::max_queue_len, "observations queued at most (MRPT)")
          .add("grab_decimation", &K::grab_decimation, "keep 1 of N observations (MRPT)")
          .add("sensorLabel", &K::sensorLabel, "label of the star-tracker observations")
          .choice("image_source", &K::image_source, {"simulated", "camera"},
                  "where frames come from")
          .required()
          .add("image_label", &K::image_label, "label of the emitted frames")
          .add("emit_image", &K::emit_image, "also emit the frames")
          .add("camera_file", &K::camera_file,
               "calibration: .yaml/.yml/.xml or .ini; empty = the scenario's camera")
          .add("camera_file_section", &K::camera_file_section, "section of an .ini camera_file")
          .add("camera_section", &K::camera_section,
               "image_source = camera: section of MRPT's CCameraSensor keys; empty = this one")
          .add("frame_rate_hz", &K::frame_rate_hz,
               "image_source = camera: [Hz] stamp frame k at frame_start_time + k / rate (a "
               "recorded folder or video); 0 = the grabber's clock")
          .range(0, 1000)
          .add("frame_start_time", &K::frame_start_time,
               "with frame_rate_hz: UTC of frame 0, YYYY-MM-DDTHH:MM:SS; empty = the first "
               "frame's grabber stamp")
          .add("scenario_file", &K::scenario_file, "image_source = simulated: the scenario played")
          .add("seed", &K::seed, "image_source = simulated: run seed; empty = the scenario's")
          .add("truth_label", &K::truth_label, "image_source = simulated: label of the truth")
          .add("scenario_head", &K::scenario_head,
               "image_source = simulated: the scenario's camera head (head_sections order)")
          .add("mount_ypr_deg", &K::mount_ypr_deg,
               "[deg] yaw pitch roll (MRPT CPose3D) of body-from-camera: the tracker's mounting "
               "and its observations' sensor pose (default: a simulated head's, else 0 0 0)")
          .add("database_file", &K::database_file, "a saved star database; empty = build one")
          .add("catalog_file", &K::catalog_file, "catalog of the build; empty = the default")
          .add("mag_limit", &K::mag_limit, "magnitude limit of the build")
          .add("epoch_jyear", &K::epoch_jyear, "[Julian year] of the build; 0 = scenario's or now")
          .add("aberration", &K::aberration, "annual aberration in the build")
          .include(trackerIniSchema(), &K::tracker);
  return s;
}

StarTrackerSensorKeys readStarTrackerSensorKeys(const IniReader& r, const std::string& section) {
  StarTrackerSensorKeys k;
  const std::string source = r.str(section, "image_source", "");
  const std::string cam_sec = r.str(section, "camera_section", section);
  if (source == "camera" && cam_sec == section)
    starTrackerSensorSchema().readKnown(r, section, k);
  else
    starTrackerSensorSchema().read(r, section, k);
  checkTrackerOptions(r, section, k.tracker);
  return k;
}

bool isStarTrackerSensorSection(const mrpt::config::CConfigFileBase& cfg,
                                const std::string& section) {
  return cfg.read_string(section, "driver", "", false) == "CStarTrackerSensor";
}

std::string printStarTrackerSensorSection(const IniReader& r, const std::string& section) {
  std::string text =
      starTrackerSensorSchema().print(section, readStarTrackerSensorKeys(r, section));
  // With a simulated source these default to the scenario's sensor at initialize(), not to
  // TrackerOptions': unset, they print empty (an empty number is an absent key), so that the
  // printed section runs as the original does.
  if (r.str(section, "image_source", "") != "simulated") return text;
  for (const char* key : {"exposure_s", "gain_e_per_adu", "read_noise_adu"}) {
    if (r.has(section, key)) continue;
    const std::string line = std::string("\n") + key + " = ";
    const std::size_t at = text.find(line);
    if (at == std::string::npos) continue;
    const std::size_t end = text.find('\n', at + line.size());
    text.replace(at, end - at, line.substr(0, line.size()) + "\n# (empty: the scenario's)");
  }
  return text;
}

}  // namespace st
