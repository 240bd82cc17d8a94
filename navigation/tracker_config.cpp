#include "navigation/tracker_config.hpp"

#include <mrpt/config/CConfigFile.h>

#include <filesystem>

#include "catalog/database_recipe.hpp"
#include "catalog/star_catalog.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "config/ini_reader.hpp"
#include "sensors/mrpt/pipeline_ini.hpp"

namespace st {

namespace {

std::string resolvePath(const std::string& p, const std::string& base_dir) {
  if (p.empty() || std::filesystem::path(p).is_absolute()) return p;
  return (std::filesystem::path(base_dir) / p).string();
}

}  // namespace

void readFusionSections(const IniReader& r, NavigatorOptions& n,
                        const std::set<std::string>& extra_navigator_keys) {
  std::set<std::string> nav_keys = {"reinit_after_rejections", "reorder_window_s",
                                    "gyro_gap_factor", "rate_window_s", "camera_label",
                                    "gyro_label", "truth_label", "star_tracker_label"};
  nav_keys.insert(extra_navigator_keys.begin(), extra_navigator_keys.end());
  r.onlyKeys("filter", {"arw_deg_rt_h", "rrw_deg_h_rt_h", "bias_sigma_deg_h", "gate_probability",
                        "gate", "update", "max_star_vectors"});
  r.onlyKeys("navigator", nav_keys);
  FusionOptions& f = n.fusion;
  // [filter]: gyro datasheet numbers.
  f.filter = MekfOptions::fromDatasheet(r.num("filter", "arw_deg_rt_h", 0.15),
                                        r.num("filter", "rrw_deg_h_rt_h", 0.5),
                                        r.num("filter", "bias_sigma_deg_h", 10.0));
  f.filter.gate_probability = r.num("filter", "gate_probability", f.filter.gate_probability);
  f.filter.gate_enabled = r.boolean("filter", "gate", f.filter.gate_enabled);
  f.filter.max_star_vectors = r.integer("filter", "max_star_vectors", f.filter.max_star_vectors);
  const std::string update = r.str("filter", "update", toString(f.update));
  if (update != "attitude" && update != "stars")
    throw InputError(r.where("filter", "update") + " = '" + update + "': attitude or stars");
  f.update = update == "stars" ? FusionOptions::Update::kStarVectors
                               : FusionOptions::Update::kAttitude;
  // [navigator]
  f.reinit_after_rejections =
      r.integer("navigator", "reinit_after_rejections", f.reinit_after_rejections);
  f.reorder_window_s = r.num("navigator", "reorder_window_s", f.reorder_window_s);
  f.gyro_gap_factor = r.num("navigator", "gyro_gap_factor", f.gyro_gap_factor);
  f.rate_window_s = r.num("navigator", "rate_window_s", f.rate_window_s);
  n.camera_label = r.str("navigator", "camera_label", n.camera_label);
  n.gyro_label = r.str("navigator", "gyro_label", n.gyro_label);
  n.truth_label = r.str("navigator", "truth_label", n.truth_label);
  n.star_tracker_label = r.str("navigator", "star_tracker_label", n.star_tracker_label);
  std::string why;
  if (!f.isValid(&why)) throw InputError(r.where("navigator") + ": " + why);
}

NavigatorOptions liveNavigatorOptions(const mrpt::config::CConfigFileBase& cfg,
                                      const std::string& source, bool* enabled) {
  const IniReader r{cfg, source};
  NavigatorOptions o;
  o.fusion.reorder_window_s = 0.5;
  readFusionSections(r, o, {"enabled"});
  *enabled = r.boolean("navigator", "enabled", true);
  return o;
}

TrackerConfig TrackerConfig::load(const std::string& path) {
  if (!std::filesystem::is_regular_file(path))
    throw InputError(path + ": tracker config not found");
  mrpt::config::CConfigFile cfg(path);
  const std::string dir = std::filesystem::path(path).parent_path().string();
  return fromConfig(cfg, path, dir.empty() ? "." : dir);
}

TrackerConfig TrackerConfig::fromConfig(const mrpt::config::CConfigFileBase& cfg,
                                        const std::string& source, const std::string& base_dir) {
  const IniReader r{cfg, source};
  TrackerConfig c;
  c.source = source;
  r.onlyKeys("pipeline", pipelineIniKeys());
  r.onlyKeys("database", {"path", "catalog", "mag_limit", "epoch_jyear", "aberration"});
  NavigatorOptions& n = c.nav;
  readFusionSections(r, n, {});

  // [pipeline]
  readPipelineOptions(r, "pipeline", n.pipeline);
  std::string why;
  if (!n.isValid(&why)) throw InputError(source + ": " + why);

  // [database]
  c.database.path = resolvePath(r.str("database", "path", ""), base_dir);
  c.database.catalog = resolvePath(r.str("database", "catalog", ""), base_dir);
  c.database.mag_limit = r.num("database", "mag_limit", c.database.mag_limit);
  c.database.epoch_jyear = r.num("database", "epoch_jyear", c.database.epoch_jyear);
  c.database.aberration = r.boolean("database", "aberration", c.database.aberration);

  // [camera]
  if (cfg.sectionExists("camera")) c.camera = CameraModel::loadIni(cfg, "camera", source);
  return c;
}

StarDatabase makeDatabase(const DatabaseSource& src, const CameraModel& camera,
                          double data_epoch_jyear) {
  if (!src.path.empty()) return StarDatabase::load(src.path);
  const std::string cat_path =
      src.catalog.empty() ? StarDatabase::defaultCatalogPath() : src.catalog;
  CameraDatabaseRecipe r;
  r.diagonal_fov_rad = 2.0 * camera.halfDiagonalFov();
  r.pixel_scale_rad = camera.pixelScale();
  r.mag_limit = src.mag_limit;
  r.epoch_jyear = src.epoch_jyear > 0 ? src.epoch_jyear : data_epoch_jyear;
  r.aberration = src.aberration;
  return StarDatabase::build(loadCatalog(cat_path), databaseParams(r));
}

}  // namespace st
