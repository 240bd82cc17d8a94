#include "navigation/tracker_config.hpp"

#include "catalog/database_cache.hpp"

#include <mrpt/config/CConfigFile.h>

#include <filesystem>

#include "catalog/database_recipe.hpp"
#include "catalog/star_catalog.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "config/ini_kind.hpp"
#include "config/ini_reader.hpp"
#include "sensors/mrpt/pipeline_ini.hpp"
#include "sensors/mrpt/camera_ini.hpp"

namespace st {

namespace {

std::string resolvePath(const std::string& p, const std::string& base_dir) {
  if (p.empty() || std::filesystem::path(p).is_absolute()) return p;
  return (std::filesystem::path(base_dir) / p).string();
}

const SectionSchema<DatabaseSource>& databaseIniSchema() {
  using D = DatabaseSource;
  static const auto s =
      SectionSchema<D>()
          .add("path", &D::path, "a saved star database; empty = build one in memory")
          .add("catalog", &D::catalog, "catalog of the build; empty = the default")
          .add("mag_limit", &D::mag_limit, "magnitude limit of the build")
          .add("epoch_jyear", &D::epoch_jyear, "[Julian year] of the build; 0 = the data's")
          .add("aberration", &D::aberration, "annual aberration in the build");
  return s;
}

}  // namespace

NavigatorOptions liveNavigatorOptions(const mrpt::config::CConfigFileBase& cfg,
                                      const std::string& source, bool* enabled) {
  const IniReader r{cfg, source};
  const LiveIniKeys k = readLiveIni(r);
  *enabled = k.navigator.enabled;
  return k.navigator.nav;
}

bool isTrackerIni(const IniReader& r) { return iniKind(r) == "a tracker file"; }

TrackerIniKeys readTrackerIni(const IniReader& r) {
  requireIniKind(r, "a tracker file", "replay --config");
  r.onlySections(trackerIniSections(), "a tracker file");
  TrackerIniKeys k;
  readFusionSections(r, k.nav);
  readPipelineOptions(r, "pipeline", k.nav.pipeline);
  std::string why;
  if (!k.nav.isValid(&why)) throw InputError(r.source + ": " + why);
  databaseIniSchema().read(r, "database", k.database);
  if (r.cfg.sectionExists("camera")) {
    loadCameraIni(r, "camera");  // the checks of the camera itself
    k.camera.emplace();
    cameraIniSchema().read(r, "camera", *k.camera);
  }
  return k;
}

std::string printTrackerIni(const TrackerIniKeys& k) {
  std::string s = printFusionSections(k.nav) + "\n" +
                  pipelineIniSchema().print("pipeline", k.nav.pipeline) + "\n" +
                  databaseIniSchema().print("database", k.database);
  if (k.camera) s += "\n" + cameraIniSchema().print("camera", *k.camera);
  return s;
}

TrackerConfig TrackerConfig::load(const std::string& path) {
  if (!std::filesystem::is_regular_file(path))
    throw InputError(path + ": tracker config not found");
  const auto file = openIniFile(path);
  const mrpt::config::CConfigFile& cfg = *file;
  const std::string dir = std::filesystem::path(path).parent_path().string();
  return fromConfig(cfg, path, dir.empty() ? "." : dir);
}

TrackerConfig TrackerConfig::fromConfig(const mrpt::config::CConfigFileBase& cfg,
                                        const std::string& source, const std::string& base_dir) {
  const IniReader r{cfg, source};
  const TrackerIniKeys k = readTrackerIni(r);
  TrackerConfig c;
  c.source = source;
  c.nav = k.nav;
  c.database = k.database;
  c.database.path = resolvePath(k.database.path, base_dir);
  c.database.catalog = resolvePath(k.database.catalog, base_dir);
  if (k.camera) c.camera = loadCameraIni(r, "camera");
  return c;
}

std::shared_ptr<const StarDatabase> makeDatabase(const DatabaseSource& src,
                                                 const CameraModel& camera,
                                                 double data_epoch_jyear) {
  if (!src.path.empty()) return std::make_shared<const StarDatabase>(StarDatabase::load(src.path));
  CameraDatabaseRecipe r;
  r.diagonal_fov_rad = 2.0 * camera.halfDiagonalFov();
  r.pixel_scale_rad = camera.pixelScale();
  r.mag_limit = src.mag_limit;
  r.epoch_jyear = src.epoch_jyear > 0 ? src.epoch_jyear : data_epoch_jyear;
  r.aberration = src.aberration;
  return cameraDatabase(r, src.catalog);
}

}  // namespace st
