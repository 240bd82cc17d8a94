#include "sensors/mrpt/camera_ini.hpp"

#include <mrpt/config/CConfigFile.h>
#include <mrpt/img/TCamera.h>

#include "common/conventions.hpp"
#include "common/errors.hpp"

namespace st {

const SectionSchema<CameraIniKeys>& cameraIniSchema() {
  using K = CameraIniKeys;
  static const auto schema =
      SectionSchema<K>()
          .add("resolution", &K::resolution, "[width height] image size in pixels")
          .required()
          .add("fov_deg", &K::fov_deg,
               "[deg] horizontal field of view; replaces fx fy cx cy (0 = use them)")
          .add("fx", &K::fx, "[px] focal length along x (columns)")
          .add("fy", &K::fy, "[px] focal length along y (rows)")
          .add("cx", &K::cx, "[px] principal point column")
          .add("cy", &K::cy, "[px] principal point row")
          .add("dist", &K::dist, "[k1 k2 p1 p2 k3] OpenCV radial-tangential distortion")
          .add("focal_length", &K::focal_length, "[m] physical focal length (MRPT TCamera; not used)");
  return schema;
}

CameraModel loadCameraIni(const mrpt::config::CConfigFileBase& cfg, const std::string& section,
                          const std::string& source_name) {
  return loadCameraIni(IniReader{cfg, source_name}, section);
}

CameraModel loadCameraIni(const IniReader& r, const std::string& section) {
  CameraIniKeys k;
  cameraIniSchema().read(r, section, k);
  const std::string where = r.where(section);
  if (k.resolution.size() != 2)
    throw InputError(r.whereKey(section, "resolution") + ": must be [width height]");
  for (double v : k.resolution)  // before the cast to int (a fuzz finding)
    if (!(v >= 1 && v <= 1e6))
      throw InputError(r.whereKey(section, "resolution") + ": width and height must be in [1, 1000000] px");
  const int w = static_cast<int>(k.resolution[0]), h = static_cast<int>(k.resolution[1]);
  const Distortion dist = distortionFromVector(k.dist, r.whereKey(section, "dist"));
  if (k.fov_deg != 0) {  // 0 is the printed "not used"
    // Either form, never both: two sources of the focal length would silently disagree.
    for (const char* key : {"fx", "fy", "cx", "cy"})
      if (r.has(section, key))
        throw InputError(r.whereKey(section, key) + ": give either fov_deg or fx fy cx cy");
    if (!(k.fov_deg > 0 && k.fov_deg < 180))  // fromFov's check, naming the file and key
      throw InputError(r.whereKey(section, "fov_deg") + ": must be in (0, 180) deg, got " +
                       std::to_string(k.fov_deg));
    const CameraModel cam = CameraModel::fromFov(w, h, deg2rad(k.fov_deg));
    return CameraModel(w, h, cam.fx(), cam.fy(), cam.cx(), cam.cy(), dist);
  }
  for (const char* key : {"fx", "fy", "cx", "cy"})
    if (!r.has(section, key))
      throw InputError(r.whereKey(section, key) + ": missing key (or give fov_deg)");
  return CameraModel(w, h, k.fx, k.fy, k.cx, k.cy, dist, where);
}

CameraIniKeys cameraIniKeys(const CameraModel& cam) {
  CameraIniKeys k;
  k.resolution = {static_cast<double>(cam.width()), static_cast<double>(cam.height())};
  k.fx = cam.fx();
  k.fy = cam.fy();
  k.cx = cam.cx();
  k.cy = cam.cy();
  const Distortion& d = cam.distortion();
  k.dist = {d.k1, d.k2, d.p1, d.p2, d.k3};
  return k;
}

CameraModel loadCameraIniFile(const std::string& path, const std::string& section) {
  requireCameraFile(path);
  const auto file = openIniFile(path);
  const mrpt::config::CConfigFile& cfg = *file;
  if (!cfg.sectionExists(section)) throw InputError(path + ": missing section [" + section + "]");
  return loadCameraIni(cfg, section, path);
}

CameraModel cameraFromTCamera(const mrpt::img::TCamera& c) {
  CameraModel cam(static_cast<int>(c.ncols), static_cast<int>(c.nrows), c.fx(), c.fy(), c.cx(),
                  c.cy(), Distortion{c.k1(), c.k2(), c.p1(), c.p2(), c.k3()});
  return cam;
}

mrpt::img::TCamera toTCamera(const CameraModel& cam) {
  mrpt::img::TCamera c;
  c.ncols = static_cast<uint32_t>(cam.width());
  c.nrows = static_cast<uint32_t>(cam.height());
  c.setIntrinsicParamsFromValues(cam.fx(), cam.fy(), cam.cx(), cam.cy());
  const Distortion& d = cam.distortion();
  c.setDistortionPlumbBob(d.k1, d.k2, d.p1, d.p2, d.k3);
  return c;
}

void registerIniCameraReader() { setIniCameraReader(loadCameraIniFile); }

}  // namespace st
