// Reading and printing a scenario .ini through the section schemas (scenario.hpp lists the
// sections): one strict reader for every section, and the effective configuration.
#include <mrpt/config/CConfigFileBase.h>

#include <algorithm>
#include <filesystem>

#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "common/utc_time.hpp"
#include "config/ini_kind.hpp"
#include "sensors/sim/scenario.hpp"
#include "sensors/mrpt/camera_ini.hpp"

namespace st {

namespace {

const SectionSchema<ScenarioKeys>& scenarioKeysSchema() {
  using S = ScenarioKeys;
  static const auto schema =
      SectionSchema<S>()
          .add("duration_s", &S::duration_s, "[s] run length, > 0")
          .range(1e-3, 864000)
          .add("frame_rate_hz", &S::frame_rate_hz, "[Hz] camera frame rate, > 0")
          .range(1e-3, 1000)
          .add("start_time", &S::start_time, "UTC of t = 0, YYYY-MM-DDTHH:MM:SS (empty = start_jyear)")
          .add("start_jyear", &S::start_jyear, "[Julian year] t = 0 when start_time is empty")
          .add("seed", &S::seed, "default run seed (the CLI's --seed overrides it)")
          .add("database", &S::database, "star database file; empty = build from catalog")
          .add("catalog", &S::catalog, "catalog for the in-memory build; empty = the default")
          .add("mag_limit", &S::mag_limit, "[mag] faintest star rendered (in-memory build)")
          .add("aberration", &S::aberration, "apparent places (annual aberration), in-memory build")
          .add("camera_section", &S::camera_section, "section of the camera model")
          .add("sensor_section", &S::sensor_section, "section of the optics + detector model")
          .add("motion_section", &S::motion_section, "section of the true motion")
          .add("gyro_section", &S::gyro_section, "section of the gyro (absent = no gyro)")
          .add("faults_section", &S::faults_section, "section of the faults (absent = none)")
          .add("orbit_section", &S::orbit_section,
               "section of the observer's circular orbit (absent = none: no aberration of its "
               "own velocity)")
          .add("head_sections", &S::head_sections,
               "sections of several camera heads, comma-separated, one per head (empty = one head, CAMERA, "
               "along the body's +z)");
  return schema;
}

const SectionSchema<HeadKeys>& headKeysSchema() {
  using K = HeadKeys;
  static const auto schema =
      SectionSchema<K>()
          .add("label", &K::label, "rawlog label of the head's images (required, unique)")
          .add("mount_ypr_deg", &K::mount_ypr_deg,
               "[deg] yaw pitch roll (MRPT CPose3D) of body-from-camera: the images' cameraPose")
          .add("faults_section", &K::faults_section,
               "section of the head's camera faults (empty = the scenario's faults_section)");
  return schema;
}

const SectionSchema<ScenarioGyroKeys>& gyroKeysSchema() {
  using G = ScenarioGyroKeys;
  static const auto schema =
      SectionSchema<G>()
          .include(gyroParamsSchema(), &G::params)
          .add("initial_bias_deg_h", &G::initial_bias_deg_h, "[deg/h] x y z turn-on bias of the run");
  return schema;
}

void requireSection(const IniReader& r, const std::string& sec) {
  if (r.cfg.sectionExists(sec)) return;
  std::vector<std::string> present;
  r.cfg.getAllSections(present);
  const std::string near = closestKey(sec, present);
  throw InputError(r.where(sec) + ": missing section" +
                   (near.empty() ? "" : " (is [" + near + "] a misspelling of it?)"));
}

/// A section named by a [scenario] key: one the user wrote must exist (a typo must not turn
/// into "no gyro" or default values); the default name may be absent where allowed.
void checkNamedSection(const IniReader& r, const char* key, const std::string& sec,
                       bool required) {
  if (r.cfg.sectionExists(sec)) return;
  if (r.has("scenario", key))
    throw InputError(r.whereKey("scenario", key) + " = '" + sec + "': no section [" + sec + "]");
  if (required) requireSection(r, sec);
}

}  // namespace

namespace {
/// [scenario] and the sections its keys `k` name, heads and their faults included.
std::set<std::string> sectionsNamedBy(const IniReader& r, const ScenarioKeys& k) {
  std::set<std::string> out = {"scenario",        k.camera_section, k.sensor_section,
                               k.motion_section,  k.gyro_section,   k.faults_section,
                               k.orbit_section};
  for (const std::string& head : k.head_sections) {
    out.insert(head);
    const std::string faults = r.str(head, "faults_section", "");
    if (!faults.empty()) out.insert(faults);
  }
  return out;
}
}  // namespace

std::set<std::string> scenarioSectionNames(const IniReader& r) {
  ScenarioKeys k;
  scenarioKeysSchema().read(r, "scenario", k);
  return sectionsNamedBy(r, k);
}

ScenarioIni readScenarioIni(const IniReader& r) {
  ScenarioIni sc;
  const std::string S = "scenario";
  if (!r.cfg.sectionExists(S)) {
    const std::string kind = iniKind(r);
    if (!kind.empty())
      throw InputError(r.source + ": this is " + kind + "; a scenario file has a [scenario] section");
  }
  requireSection(r, S);
  ScenarioKeys& k = sc.main;
  scenarioKeysSchema().read(r, S, k);
  if (!(k.duration_s > 0)) throw InputError(r.whereKey(S, "duration_s") + ": must be > 0");
  if (!(k.frame_rate_hz > 0)) throw InputError(r.whereKey(S, "frame_rate_hz") + ": must be > 0");
  if (!k.start_time.empty()) parseUtc(k.start_time, r.whereKey(S, "start_time"));
  checkNamedSection(r, "camera_section", k.camera_section, true);
  checkNamedSection(r, "sensor_section", k.sensor_section, false);
  checkNamedSection(r, "motion_section", k.motion_section, true);
  checkNamedSection(r, "gyro_section", k.gyro_section, false);
  checkNamedSection(r, "faults_section", k.faults_section, false);
  checkNamedSection(r, "orbit_section", k.orbit_section, false);
  sc.camera = loadCameraIni(r, k.camera_section);
  sc.sensor = SensorParams::fromConfig(r, k.sensor_section);
  sc.motion = readMotionKeys(r, k.motion_section);
  MotionProfile::fromKeys(sc.motion, r.where(k.motion_section));  // validates the values
  if (r.cfg.sectionExists(k.gyro_section)) {
    ScenarioGyroKeys g;
    gyroKeysSchema().read(r, k.gyro_section, g);
    const std::string err = g.params.validate();
    if (!err.empty()) throw InputError(r.where(k.gyro_section) + ": " + err);
    sc.gyro = g;
  }
  sc.faults = FaultParams::fromConfig(r, k.faults_section);
  if (r.cfg.sectionExists(k.orbit_section)) {
    CircularOrbit o;
    orbitSchema().read(r, k.orbit_section, o);
    const std::string err = o.validate();
    if (!err.empty()) throw InputError(r.where(k.orbit_section) + ": " + err);
    sc.orbit = o;
  }
  for (const std::string& sec : k.head_sections) {
    if (!r.cfg.sectionExists(sec))
      throw InputError(r.whereKey(S, "head_sections") + ": no section [" + sec + "]");
    HeadKeys h;
    headKeysSchema().read(r, sec, h);
    if (h.label.empty()) throw InputError(r.where(sec) + ": 'label' is required");
    // The label names the head's image files too (<label>_000000.png).
    if (h.label.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_-") !=
        std::string::npos)
      throw InputError(r.whereKey(sec, "label") + " = '" + h.label +
                       "': only letters, digits, '_' and '-'");
    for (const HeadKeys& other : sc.heads)
      if (other.label == h.label)
        throw InputError(r.whereKey(sec, "label") + " = '" + h.label + "': another head's label");
    if (!h.mount_ypr_deg.allFinite())
      throw InputError(r.whereKey(sec, "mount_ypr_deg") + ": not finite");
    if (!h.faults_section.empty() && !r.cfg.sectionExists(h.faults_section))
      throw InputError(r.whereKey(sec, "faults_section") + " = '" + h.faults_section +
                       "': no section [" + h.faults_section + "]");
    sc.head_faults.push_back(h.faults_section.empty()
                                 ? sc.faults
                                 : FaultParams::fromConfig(r, h.faults_section));
    sc.heads.push_back(h);
  }
  // Last: a section the file names but lacks is reported as such above, by its key.
  std::set<std::string> sections = sectionsNamedBy(r, k);  // keys read once, above
  if (isLiveIni(r))  // a live .ini that holds its simulated sensors' scenario
    for (const auto& s : liveIniSections(r)) sections.insert(s);
  r.onlySections(sections, "a scenario file");
  return sc;
}

std::string printScenarioIni(const ScenarioIni& sc) {
  const ScenarioKeys& k = sc.main;
  std::string out = scenarioKeysSchema().print("scenario", k) + "\n";
  // No gyro: its (default) section is absent, and naming an absent section is an error.
  const std::string named = "\ngyro_section = " + k.gyro_section + "\n";
  if (const auto at = out.find(named); !sc.gyro && at != std::string::npos)
    out.replace(at, named.size(), "\n# gyro_section = " + k.gyro_section + " (absent: no gyro)\n");
  const std::string orbit_named = "\norbit_section = " + k.orbit_section + "\n";
  if (const auto at = out.find(orbit_named); !sc.orbit && at != std::string::npos)
    out.replace(at, orbit_named.size(),
                "\n# orbit_section = " + k.orbit_section + " (absent: no orbit)\n");
  out += cameraIniSchema().print(k.camera_section, cameraIniKeys(sc.camera)) + "\n";
  out += sensorParamsSchema().print(k.sensor_section, sc.sensor) + "\n";
  out += motionSchema(sc.motion.type).print(k.motion_section, sc.motion) + "\n";
  if (sc.gyro) out += gyroKeysSchema().print(k.gyro_section, *sc.gyro) + "\n";
  out += faultParamsSchema().print(k.faults_section, sc.faults);
  if (sc.orbit) out += "\n" + orbitSchema().print(k.orbit_section, *sc.orbit);
  std::vector<std::string> printed = {k.faults_section};
  for (std::size_t h = 0; h < sc.heads.size(); ++h) {
    out += "\n" + headKeysSchema().print(k.head_sections[h], sc.heads[h]);
    const std::string& fs = sc.heads[h].faults_section;
    if (fs.empty() || std::find(printed.begin(), printed.end(), fs) != printed.end()) continue;
    printed.push_back(fs);
    out += "\n" + faultParamsSchema().print(fs, sc.head_faults[h]);
  }
  return out;
}

Scenario Scenario::fromConfig(const mrpt::config::CConfigFileBase& cfg, const std::string& source,
                              const std::string& base_dir) {
  const IniReader r{cfg, source};
  const ScenarioIni ini = readScenarioIni(r);
  const ScenarioKeys& k = ini.main;
  Scenario sc;
  sc.source = source;
  sc.duration_s = k.duration_s;
  sc.frame_rate_hz = k.frame_rate_hz;
  sc.start_unix_s = k.start_time.empty()
                        ? unixSecondsFromJulianYear(k.start_jyear)
                        : parseUtc(k.start_time, r.whereKey("scenario", "start_time"));
  sc.seed = k.seed;
  auto path = [&](std::string p) {
    if (!p.empty() && std::filesystem::path(p).is_relative())
      p = (std::filesystem::path(base_dir) / p).string();
    return p;
  };
  sc.database_path = path(k.database);
  sc.catalog_path = path(k.catalog);
  for (const auto& [key, file] : {std::pair<const char*, const std::string&>{"database", sc.database_path},
                                  {"catalog", sc.catalog_path}}) {
    if (!file.empty() && !std::filesystem::is_regular_file(file))
      throw InputError(r.whereKey("scenario", key) + " = '" + r.str("scenario", key, "") +
                       "': no such file (" + file + ")");
  }
  sc.mag_limit = k.mag_limit;
  sc.aberration = k.aberration;
  sc.camera = ini.camera;
  sc.sensor = ini.sensor;
  sc.motion = MotionProfile::fromKeys(ini.motion, r.where(k.motion_section));
  if (ini.gyro) {
    sc.gyro = ini.gyro->params;
    sc.gyro_initial_bias_rad_s = ini.gyro->initial_bias_deg_h * (kRadPerDeg / 3600.0);
  }
  sc.faults = ini.faults;
  sc.orbit = ini.orbit;
  if (!ini.heads.empty()) {
    sc.heads.clear();
    for (std::size_t h = 0; h < ini.heads.size(); ++h) {
      const HeadKeys& hk = ini.heads[h];
      CameraHead head;
      head.label = hk.label;
      head.mount_ypr_deg = hk.mount_ypr_deg;
      head.R_body_cam = head.pose().getRotationMatrix().asEigen();
      if (!hk.faults_section.empty()) head.faults = ini.head_faults[h];
      sc.heads.push_back(head);
    }
  }
  return sc;
}

}  // namespace st
