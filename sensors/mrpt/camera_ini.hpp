/// @file camera_ini.hpp
/// The camera in MRPT's words: an .ini section in mrpt::img::TCamera style, and TCamera itself
/// (CObservationImage::cameraParams carries it in rawlogs). The camera stage
/// (sensors/camera/camera_model.hpp) is MRPT-free; these adapters convert at the MRPT edge.
#pragma once
#include <string>
#include <vector>

#include "config/schema.hpp"
#include "sensors/camera/camera_model.hpp"

namespace mrpt::config {
class CConfigFileBase;
}
namespace mrpt::img {
class TCamera;
}

namespace st {

/// The keys of a camera .ini section: MRPT TCamera's (resolution, fx, fy, cx, cy, dist,
/// focal_length) plus the shorthand fov_deg, which replaces fx fy cx cy (square pixels,
/// principal point at the centre). Schema: cameraIniSchema().
struct CameraIniKeys {
  std::vector<double> resolution;  ///< [w h], required
  double fov_deg = 0;              ///< 0 = not used (fx fy cx cy given)
  double fx = 0, fy = 0, cx = 0, cy = 0;
  std::vector<double> dist = {0, 0, 0, 0, 0};
  double focal_length = 0;  ///< [m] informational (TCamera writes it); not used
};
const SectionSchema<CameraIniKeys>& cameraIniSchema();

/// An MRPT .ini section in mrpt::img::TCamera style: `resolution = [w h]`, `cx`, `cy`,
/// `fx`, `fy`, `dist = [k1 k2 p1 p2 k3]`, or `resolution` with `fov_deg` (CameraIniKeys).
/// Strict: throws InputError naming the source, section and key (unknown keys too).
CameraModel loadCameraIni(const IniReader& r, const std::string& section);
CameraModel loadCameraIni(const mrpt::config::CConfigFileBase& cfg, const std::string& section,
                          const std::string& source_name = "ini");
CameraModel loadCameraIniFile(const std::string& path, const std::string& section);
/// Installs loadCameraIniFile as CameraModel::loadFile's reader of .ini files. Every program
/// and plugin that links the MRPT adapters calls it once at start-up.
void registerIniCameraReader();

/// The .ini keys of `cam` in the explicit form (fx fy cx cy; loadCameraIni gives it back).
CameraIniKeys cameraIniKeys(const CameraModel& cam);

/// MRPT's camera parameters and back.
CameraModel cameraFromTCamera(const mrpt::img::TCamera& cam);
mrpt::img::TCamera toTCamera(const CameraModel& cam);

}  // namespace st
